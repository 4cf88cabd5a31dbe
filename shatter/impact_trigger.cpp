#include "shatter/impact_trigger.hpp"

#include <algorithm>
#include <map>

namespace shellfrac::shatter {

std::vector<BodyImpact> gather_impacts(const std::vector<rigid::ContactPoint>& contacts) {
  struct Sum {
    BodyImpact impact;
    rigid::Vec3 push = rigid::Vec3::Zero();
  };
  std::map<std::pair<int, int>, Sum> sums;
  const auto add = [&](int body, int partner, const rigid::ContactPoint& c, const rigid::Vec3& push) {
    Sum& s = sums[{body, partner}];
    s.impact.body = body;
    s.impact.partner = partner;
    s.impact.impulse += c.impulse;
    s.impact.partner_impulse += c.impulse;
    s.impact.point += c.impulse * c.point;
    s.impact.approach_speed += c.impulse * std::max(c.approach_speed, 0.0);
    s.push += c.impulse * push;
  };
  for (const rigid::ContactPoint& c : contacts) {
    if (!(c.impulse > 0)) continue;
    add(c.a, c.b, c, c.normal);   // a is pushed along +normal
    add(c.b, c.a, c, -c.normal);  // b along -normal
  }
  std::vector<BodyImpact> out;
  for (auto& [key, s] : sums) {
    BodyImpact i = s.impact;
    i.point /= i.impulse;
    i.approach_speed /= i.impulse;
    i.direction = s.push.norm() > 0 ? rigid::Vec3(s.push.normalized()) : rigid::Vec3::Zero();
    out.push_back(i);
  }
  return out;
}

BodyImpact merge_impacts(const std::vector<BodyImpact>& steps) {
  BodyImpact m;
  rigid::Vec3 push = rigid::Vec3::Zero();
  double largest = 0;
  for (const BodyImpact& i : steps) {
    if (!(i.impulse > 0)) continue;
    m.body = i.body;
    m.impulse += i.impulse;
    m.point += i.impulse * i.point;
    push += i.impulse * i.direction;
    m.approach_speed = std::max(m.approach_speed, i.approach_speed);
    if (i.impulse > largest) {
      largest = i.impulse;
      m.partner = i.partner;
      m.partner_impulse = i.partner_impulse;
    }
  }
  if (m.impulse > 0) {
    m.point /= m.impulse;
    m.direction = push.norm() > 0 ? rigid::Vec3(push.normalized()) : rigid::Vec3::Zero();
  }
  return m;
}

}  // namespace shellfrac::shatter
