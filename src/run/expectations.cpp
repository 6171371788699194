#include "proxygrasp/run/expectations.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/run/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pg {

namespace {

std::string VecText(const Vec2& v) {
  return "[" + FormatDouble(v.x()) + ", " + FormatDouble(v.y()) + "]";
}

}  // namespace

std::string ExpectationText(const Expectation& e) {
  auto region = [](const Region& r) {
    if (r.kind == Region::Kind::kCircle) {
      return "within " + FormatDouble(r.radius) + " cm of " + VecText(r.center);
    }
    return "inside " + VecText(r.min) + ".." + VecText(r.max) + " cm";
  };
  // degrees come back from radians with a rounding error; a millionth is finer than any level
  auto bounds = [](double low, double high, double scale, const char* unit) {
    auto text = [scale](double v) { return FormatDouble(std::round(v * scale * 1e6) / 1e6); };
    std::string s;
    if (std::isfinite(low)) s += ">= " + text(low) + unit;
    if (std::isfinite(high)) s += std::string(s.empty() ? "" : " and ") + "<= " + text(high) + unit;
    return s;
  };
  std::string text;
  switch (e.kind) {
    case ExpectKind::kPosition:
      text = e.object + " " + region(e.region);
      break;
    case ExpectKind::kRotation:
      text = e.object + " turned " + bounds(e.minAngle, e.maxAngle, RadToDeg(1.0), " deg");
      break;
    case ExpectKind::kDisplacement:
      text = e.object + " moved " + bounds(e.above, e.below, 1.0, " cm");
      break;
    case ExpectKind::kHeld:
      text = e.object + (e.held ? " held" : " not held");
      break;
    case ExpectKind::kResting:
      text = FormatDouble(e.fraction * 100) + "% of " + e.contact + " resting on " +
             (e.OnTable() ? std::string("the table") : e.on);
      break;
    case ExpectKind::kSpeed:
      text = e.object + " never faster than " + FormatDouble(e.below) + " cm/s";
      break;
  }
  text += e.at ? " at " + FormatDouble(*e.at) + " s" : " at the end";
  std::string qualifiers;
  if (!e.variant.empty()) qualifiers += e.variant;
  if (e.mode) {
    qualifiers +=
        (qualifiers.empty() ? "" : ", ") + std::string(kProxyModeNames[static_cast<int>(*e.mode)]);
  }
  if (!qualifiers.empty()) text += " (" + qualifiers + ")";
  return text;
}

Evaluator::Evaluator(const Level& level, const LevelRun& run, const Simulation& sim)
    : m_level(level) {
  for (const Expectation& e : level.expectations) {
    if (AppliesTo(e, run, level)) m_pending.push_back(&e);
  }
  for (int i = 0; i < sim.world().ObjectCount(); ++i) {
    const ObjectState s = sim.world().Object(i);
    ObjectTrack track;
    track.start = s.pose.pos;
    track.lastAngle = s.pose.angle;
    m_objects.push_back(track);
  }
}

void Evaluator::AfterFrame(const Simulation& sim, double t,
                           std::vector<ExpectationResult>& results) {
  for (int i = 0; i < sim.world().ObjectCount(); ++i) {
    const ObjectState s = sim.world().Object(i);
    ObjectTrack& track = m_objects[static_cast<size_t>(i)];
    track.rotation += WrapAngle(s.pose.angle - track.lastAngle);
    track.lastAngle = s.pose.angle;
    track.held[static_cast<size_t>(track.frames % kHeldFrames)] = s.held;
    track.peakSpeed = std::max(track.peakSpeed, s.velocity.norm());
    ++track.frames;
  }
  // a small tolerance so an expectation at exactly a frame boundary is checked on that frame
  const double due = t + 1e-9;
  for (auto it = m_pending.begin(); it != m_pending.end();) {
    const Expectation& e = **it;
    const double at = e.at.value_or(DefaultTime(e));
    if (at <= due) {
      results.push_back(Check(e, sim));
      it = m_pending.erase(it);
    } else {
      ++it;
    }
  }
}

void Evaluator::Finish(const Simulation& sim, double t, std::vector<ExpectationResult>& results) {
  for (const Expectation* e : m_pending) {
    const double at = e->at.value_or(DefaultTime(*e));
    if (std::isfinite(at) && at > t + 1e-9) {
      results.push_back(
          {e, ExpectationText(*e), "run ended at " + FormatFixed(t, 3) + " s", false});
    } else {
      results.push_back(Check(*e, sim));
    }
  }
  m_pending.clear();
  // report in file order, whatever order they were due in
  std::stable_sort(results.begin(), results.end(),
                   [](const ExpectationResult& a, const ExpectationResult& b) {
                     return a.expectation < b.expectation;
                   });
}

// a resting expectation with no time is checked at its contact's last keyframe; others at the end
double Evaluator::DefaultTime(const Expectation& e) const {
  if (e.kind == ExpectKind::kResting) {
    for (const ScriptContact& c : m_level.script.contacts) {
      if (c.name == e.contact) return c.End();
    }
  }
  return std::numeric_limits<double>::infinity();
}

ObjectId Evaluator::ObjectIndex(const std::string& name) const {
  for (size_t i = 0; i < m_level.objects.size(); ++i) {
    if (m_level.objects[i].name == name) return static_cast<ObjectId>(i);
  }
  return kNoObject;
}

ExpectationResult Evaluator::Check(const Expectation& e, const Simulation& sim) const {
  ExpectationResult r{&e, ExpectationText(e), "", false};
  const ObjectId object = ObjectIndex(e.object);
  switch (e.kind) {
    case ExpectKind::kPosition: {
      const Vec2 p = sim.world().Object(object).pose.pos;
      r.measured = "(" + FormatFixed(p.x(), 2) + ", " + FormatFixed(p.y(), 2) + ") cm";
      r.passed = e.region.Contains(p);
      break;
    }
    case ExpectKind::kRotation: {
      const double rotation = m_objects[static_cast<size_t>(object)].rotation;
      r.measured = FormatFixed(RadToDeg(rotation), 1) + " deg";
      r.passed = rotation >= e.minAngle && rotation <= e.maxAngle;
      break;
    }
    case ExpectKind::kDisplacement: {
      const ObjectTrack& track = m_objects[static_cast<size_t>(object)];
      const double d = (sim.world().Object(object).pose.pos - track.start).norm();
      r.measured = FormatFixed(d, 3) + " cm";
      r.passed = d >= e.above && d <= e.below;
      break;
    }
    case ExpectKind::kHeld: {
      // held when the object was held in most of the last kHeldFrames frames
      const ObjectTrack& track = m_objects[static_cast<size_t>(object)];
      const size_t n = static_cast<size_t>(std::min<int64_t>(track.frames, kHeldFrames));
      const auto heldCount =
          std::count(track.held.begin(), track.held.begin() + static_cast<std::ptrdiff_t>(n), true);
      const bool isHeld = n > 0 && 2 * static_cast<size_t>(heldCount) > n;
      r.measured = std::string(isHeld ? "held" : "not held") + " (" + std::to_string(heldCount) +
                   "/" + std::to_string(n) + " frames)";
      r.passed = isHeld == e.held;
      break;
    }
    case ExpectKind::kResting: {
      int scriptIndex = -1;
      for (size_t i = 0; i < m_level.script.contacts.size(); ++i) {
        if (m_level.script.contacts[i].name == e.contact) scriptIndex = static_cast<int>(i);
      }
      const ObjectId on = e.OnTable() ? kNoObject : ObjectIndex(e.on);
      int total = 0;
      int resting = 0;
      for (const ParticleState& p : sim.world().Particles()) {
        if (sim.ScriptContactOf(p.contact) != scriptIndex) continue;
        ++total;
        if (p.restingOn == on) ++resting;
      }
      const double fraction = total > 0 ? static_cast<double>(resting) / total : 0.0;
      r.measured = std::to_string(resting) + "/" + std::to_string(total) + " particles (" +
                   FormatFixed(100.0 * fraction, 0) + "%)";
      // the loader checks that the contact is down then, so no particle means that the input
      // does not draw the script's contacts (a TUIO stream or a video names none of them)
      if (total == 0) r.measured += ": none of script contact '" + e.contact + "'";
      r.passed = total > 0 && fraction >= e.fraction;
      break;
    }
    case ExpectKind::kSpeed: {
      const double peak = m_objects[static_cast<size_t>(object)].peakSpeed;
      r.measured = "peak " + FormatFixed(peak, 2) + " cm/s";
      r.passed = peak < e.below;
      break;
    }
  }
  return r;
}

}  // namespace pg
