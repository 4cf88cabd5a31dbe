#pragma once
// Fragment classes by volume ratio (thesis sec. 3.6.1): the share of the original object's volume a piece
// holds decides how it collides and whether it may break again.
#include <string>

namespace shellfrac::shatter {

enum class FragmentClass {
  Tiny,         // ratio < VR_t: collides as its convex hull, never breaks
  Small,        // VR_t <= ratio < VR_s: collides as its mesh, never breaks
  Large,        // VR_s <= ratio < VR_l: breakable again, resampled at its next fracture event
  NearlyWhole,  // ratio >= VR_l: breakable again, reuses its parent's particles
};
const char* to_string(FragmentClass c);

struct VolumeRatios {
  double tiny = 0.05;   // VR_t
  double small = 0.2;   // VR_s
  double large = 0.98;  // VR_l
  // Empty when 0 < VR_t < VR_s < VR_l <= 1, else what is wrong.
  std::string check() const;
};

// ratio = the piece's volume / the original object's volume (descendants keep the original's).
FragmentClass classify(double ratio, const VolumeRatios& ratios);
inline bool breakable(FragmentClass c) { return c == FragmentClass::Large || c == FragmentClass::NearlyWhole; }

}  // namespace shellfrac::shatter
