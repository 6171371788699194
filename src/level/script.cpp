#include "proxygrasp/level/script.h"

#include <algorithm>
#include <cassert>

namespace pg {

namespace {

// the keyframes around t and how far t is between them (after easing), or nullopt when t is
// outside the contact's keyframes; at and after the last keyframe both are the last, s = 0
struct Segment {
  const Keyframe* a;
  const Keyframe* b;
  double s;
};

std::optional<Segment> SegmentAt(const ScriptContact& contact, double t) {
  assert(!contact.keys.empty() && "a script contact has at least one keyframe");
  const std::vector<Keyframe>& keys = contact.keys;
  if (t < keys.front().t || t > keys.back().t) return std::nullopt;

  // the segment [a, b] holding t; the last keyframe is its own segment
  const auto after = std::upper_bound(keys.begin(), keys.end(), t,
                                      [](double time, const Keyframe& k) { return time < k.t; });
  if (after == keys.end()) return Segment{&keys.back(), &keys.back(), 0.0};
  const Keyframe& a = *(after - 1);
  const Keyframe& b = *after;
  double s = (t - a.t) / (b.t - a.t);
  if (contact.interpolation == Interpolation::kSmooth) s = SmoothStep(s);
  return Segment{&a, &b, s};
}

}  // namespace

std::optional<Pose2> PoseAt(const ScriptContact& contact, double t) {
  const std::optional<Segment> seg = SegmentAt(contact, t);
  if (!seg) return std::nullopt;
  if (seg->a == seg->b) return seg->a->pose;
  // blend position and angle alike; angles are not wrapped so a key at 360 deg turns fully
  const Keyframe& a = *seg->a;
  const Keyframe& b = *seg->b;
  Pose2 pose;
  pose.pos = a.pose.pos + (b.pose.pos - a.pose.pos) * seg->s;
  pose.angle = Lerp(a.pose.angle, b.pose.angle, seg->s);
  return pose;
}

std::optional<double> HeightAt(const ScriptContact& contact, double t) {
  const std::optional<Segment> seg = SegmentAt(contact, t);
  if (!seg) return std::nullopt;
  if (seg->a == seg->b) return seg->a->height;
  return Lerp(seg->a->height, seg->b->height, seg->s);
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
    shapes.back().height = *HeightAt(contact, t);
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
