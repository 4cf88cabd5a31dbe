#include "shatter/fragment_class.hpp"

namespace shellfrac::shatter {

const char* to_string(FragmentClass c) {
  switch (c) {
    case FragmentClass::Tiny: return "tiny";
    case FragmentClass::Small: return "small";
    case FragmentClass::Large: return "large";
    case FragmentClass::NearlyWhole: return "nearly_whole";
  }
  return "?";
}

std::string VolumeRatios::check() const {
  if (!(tiny > 0 && tiny < small && small < large && large <= 1))
    return "volume ratios must satisfy 0 < tiny < small < large <= 1 (VR_t < VR_s < VR_l)";
  return "";
}

FragmentClass classify(double ratio, const VolumeRatios& r) {
  if (ratio < r.tiny) return FragmentClass::Tiny;
  if (ratio < r.small) return FragmentClass::Small;
  if (ratio < r.large) return FragmentClass::Large;
  return FragmentClass::NearlyWhole;
}

}  // namespace shellfrac::shatter
