#include "proxygrasp/level/script.h"

#include <algorithm>
#include <cassert>

namespace pg {

std::optional<Pose2> PoseAt(const ScriptContact& contact, double t) {
  assert(!contact.keys.empty() && "a script contact has at least one keyframe");
  const std::vector<Keyframe>& keys = contact.keys;
  if (t < keys.front().t || t > keys.back().t) return std::nullopt;

  // the segment [a, b] holding t; the last keyframe is its own segment
  const auto after = std::upper_bound(keys.begin(), keys.end(), t,
                                      [](double time, const Keyframe& k) { return time < k.t; });
  if (after == keys.end()) return keys.back().pose;
  const Keyframe& a = *(after - 1);
  const Keyframe& b = *after;

  // blend position and angle alike; angles are not wrapped so a key at 360 deg turns fully
  double s = (t - a.t) / (b.t - a.t);
  if (contact.interpolation == Interpolation::kSmooth) s = SmoothStep(s);
  Pose2 pose;
  pose.pos = a.pose.pos + (b.pose.pos - a.pose.pos) * s;
  pose.angle = Lerp(a.pose.angle, b.pose.angle, s);
  return pose;
}

std::vector<ContactShape> ShapesAt(const Script& script, double t,
                                   std::vector<int>* contactIndices) {
  std::vector<ContactShape> shapes;
  if (contactIndices) contactIndices->clear();
  for (size_t i = 0; i < script.contacts.size(); ++i) {
    const ScriptContact& contact = script.contacts[i];
    const std::optional<Pose2> pose = PoseAt(contact, t);
    if (!pose) continue;
    shapes.push_back(contact.shape);
    shapes.back().pose = *pose;
    if (contactIndices) contactIndices->push_back(static_cast<int>(i));
  }
  return shapes;
}

double LastKeyframeTime(const Script& script) {
  double last = 0.0;
  for (const ScriptContact& c : script.contacts) last = std::max(last, c.End());
  return last;
}

}  // namespace pg
