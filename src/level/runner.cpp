#include "proxygrasp/level/runner.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/frame_source.h"
#include "proxygrasp/sensing/recorder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace pg {

namespace {

// how many recent frames decide whether an object is held (0.1 s at 60 Hz): the held flag of a
// single frame flickers when one contact point slips for a substep
constexpr int kHeldFrames = 6;

std::string Fixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, v);
  return buffer;
}

std::string RunName(const LevelRun& run) {
  return (run.variant.empty() ? std::string("base") : run.variant) + "/" +
         kProxyModeNames[static_cast<int>(run.mode)];
}

// what the runner remembers of each object across a run
struct ObjectTrack {
  Vec2 start = Vec2::Zero();
  double lastAngle = 0.0;
  double rotation = 0.0;   // unwrapped signed rotation since the start, rad
  std::vector<bool> held;  // held flag of every frame
};

class Evaluator {
 public:
  Evaluator(const Level& level, const LevelRun& run, const Simulation& sim) : m_level(level) {
    for (const Expectation& e : level.expectations) {
      if (AppliesTo(e, run, level)) m_pending.push_back(&e);
    }
    for (int i = 0; i < sim.world().ObjectCount(); ++i) {
      const ObjectState s = sim.world().Object(i);
      m_objects.push_back({s.pose.pos, s.pose.angle, 0.0, {}});
    }
  }

  // after each frame: update object tracks, then check expectations due by time t (s)
  void AfterFrame(const Simulation& sim, double t, RunResult& out) {
    for (int i = 0; i < sim.world().ObjectCount(); ++i) {
      const ObjectState s = sim.world().Object(i);
      ObjectTrack& track = m_objects[static_cast<size_t>(i)];
      track.rotation += WrapAngle(s.pose.angle - track.lastAngle);
      track.lastAngle = s.pose.angle;
      track.held.push_back(s.held);
    }
    // a small tolerance so an expectation at exactly a frame boundary is checked on that frame
    const double due = t + 1e-9;
    for (auto it = m_pending.begin(); it != m_pending.end();) {
      const Expectation& e = **it;
      const double at = e.at.value_or(DefaultTime(e));
      if (at <= due) {
        out.results.push_back(Check(e, sim));
        it = m_pending.erase(it);
      } else {
        ++it;
      }
    }
  }

  // at the end of the run: everything still pending is checked now, or fails as not reached
  void Finish(const Simulation& sim, double t, RunResult& out) {
    for (const Expectation* e : m_pending) {
      const double at = e->at.value_or(DefaultTime(*e));
      if (std::isfinite(at) && at > t + 1e-9) {
        ExpectationResult r{e, ExpectationText(*e), "run ended at " + Fixed(t, 3) + " s", false};
        out.results.push_back(std::move(r));
      } else {
        out.results.push_back(Check(*e, sim));
      }
    }
    m_pending.clear();
    // report in file order, whatever order they were due in
    std::stable_sort(out.results.begin(), out.results.end(),
                     [](const ExpectationResult& a, const ExpectationResult& b) {
                       return a.expectation < b.expectation;
                     });
  }

 private:
  // a resting expectation with no time is checked at its contact's last keyframe; others at the end
  double DefaultTime(const Expectation& e) const {
    if (e.kind == ExpectKind::kResting) {
      for (const ScriptContact& c : m_level.script.contacts) {
        if (c.name == e.contact) return c.End();
      }
    }
    return std::numeric_limits<double>::infinity();
  }

  int ObjectIndex(const std::string& name) const {
    for (size_t i = 0; i < m_level.objects.size(); ++i) {
      if (m_level.objects[i].name == name) return static_cast<int>(i);
    }
    return -1;
  }

  ExpectationResult Check(const Expectation& e, const Simulation& sim) const {
    ExpectationResult r{&e, ExpectationText(e), "", false};
    const int object = ObjectIndex(e.object);
    switch (e.kind) {
      case ExpectKind::kPosition: {
        const Vec2 p = sim.world().Object(object).pose.pos;
        r.measured = "(" + Fixed(p.x(), 2) + ", " + Fixed(p.y(), 2) + ") cm";
        r.passed = e.region.Contains(p);
        break;
      }
      case ExpectKind::kRotation: {
        const double rotation = m_objects[static_cast<size_t>(object)].rotation;
        r.measured = Fixed(RadToDeg(rotation), 1) + " deg";
        r.passed = rotation >= e.minAngle && rotation <= e.maxAngle;
        break;
      }
      case ExpectKind::kDisplacement: {
        const ObjectTrack& track = m_objects[static_cast<size_t>(object)];
        const double d = (sim.world().Object(object).pose.pos - track.start).norm();
        r.measured = Fixed(d, 3) + " cm";
        r.passed = d >= e.above && d <= e.below;
        break;
      }
      case ExpectKind::kHeld: {
        // held when the object was held in most of the last kHeldFrames frames
        const std::vector<bool>& held = m_objects[static_cast<size_t>(object)].held;
        const size_t n = std::min<size_t>(held.size(), kHeldFrames);
        const auto heldCount =
            std::count(held.end() - static_cast<std::ptrdiff_t>(n), held.end(), true);
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
        const int on = e.OnTable() ? -1 : ObjectIndex(e.on);
        int total = 0;
        int resting = 0;
        for (const ParticleState& p : sim.world().Particles()) {
          if (sim.ScriptContactOf(p.contact) != scriptIndex) continue;
          ++total;
          if (p.restingOn == on) ++resting;
        }
        const double fraction = total > 0 ? static_cast<double>(resting) / total : 0.0;
        r.measured = std::to_string(resting) + "/" + std::to_string(total) + " particles (" +
                     Fixed(100.0 * fraction, 0) + "%)";
        r.passed = total > 0 && fraction >= e.fraction;
        break;
      }
    }
    return r;
  }

  const Level& m_level;
  std::vector<const Expectation*> m_pending;
  std::vector<ObjectTrack> m_objects;
};

void AppendObjectRows(const Simulation& sim, int64_t frame, double t, std::string& csv) {
  for (int i = 0; i < sim.world().ObjectCount(); ++i) {
    const ObjectState s = sim.world().Object(i);
    csv += std::to_string(frame) + "," + Fixed(t, 6) + "," + s.name + "," +
           Fixed(s.pose.pos.x(), 6) + "," + Fixed(s.pose.pos.y(), 6) + "," +
           Fixed(RadToDeg(s.pose.angle), 6) + "," + Fixed(s.velocity.x(), 6) + "," +
           Fixed(s.velocity.y(), 6) + "," + Fixed(RadToDeg(s.angularVelocity), 6) + "," +
           (s.held ? "1" : "0") + "\n";
  }
}

void AppendFrameRow(const FrameStats& f, double t, std::string& csv) {
  csv += std::to_string(f.frame) + "," + Fixed(t, 6) + "," + std::to_string(f.contacts) + "," +
         std::to_string(f.particles) + "," + std::to_string(f.created) + "," +
         std::to_string(f.deleted) + "," + std::to_string(f.bodies) + "," + Fixed(f.senseMs, 4) +
         "," + Fixed(f.trackMs, 4) + "," + Fixed(f.proxyMs, 4) + "," + Fixed(f.physicsMs, 4) + "," +
         Fixed(f.totalMs, 4) + "\n";
}

// a run's frames come from its script, or from the level's recording; a recorder may keep them
class RunInput {
 public:
  Status Open(const Level& level, const std::string& record, const Simulation& sim) {
    if (!level.script.recording.empty()) {
      Result<std::unique_ptr<FrameSource>> source =
          OpenFrameSource("video:" + level.script.recording);
      if (!source.ok()) return MakeError({level.script.recording}, source.error().Format());
      m_source = std::move(source.value());
    }
    if (!record.empty()) {
      const cv::Size size(sim.params().camera.width, sim.params().camera.height);
      if (Status s = m_recorder.Open(record, size, sim.params().physics.frameRate)) return s;
    }
    return std::nullopt;
  }

  // steps one frame; false (and no error) when the recording has ended
  Result<bool> Step(const Level& level, Simulation& sim) {
    if (m_source) {
      const FrameStatus status = m_source->Read(m_frame);
      if (status == FrameStatus::kEnd) return false;
      if (status != FrameStatus::kOk) {
        return MakeError({level.script.recording},
                         "frame " + std::to_string(sim.Frame()) + ": " + m_source->LastError());
      }
      if (Status s = sim.StepImage(m_frame)) return *s;
    } else if (Status s = sim.StepScript()) {
      return *s;
    }
    if (m_recorder.IsOpen()) {
      if (Status s = m_recorder.Write(sim.cameraImage())) return *s;
    }
    return true;
  }

  void Close() { m_recorder.Close(); }

 private:
  std::unique_ptr<FrameSource> m_source;
  FrameRecorder m_recorder;
  cv::Mat m_frame;
};

Result<RunResult> RunOne(const Level& level, const LevelRun& run, const RunOptions& options,
                         const FrameObserver& observer) {
  Simulation sim;
  if (Status s = sim.Start(level, RunParams(level, run))) return *s;
  RunResult out;
  out.run = run;
  out.name = RunName(run);
  out.objectsCsv = std::string(kObjectsCsvHeader) + "\n";
  out.framesCsv = std::string(kFramesCsvHeader) + "\n";

  const double frameDuration = sim.FrameDuration();
  const int64_t frames =
      options.frames >= 0
          ? options.frames
          : static_cast<int64_t>(std::ceil(level.script.duration / frameDuration - 1e-9));
  RunInput input;
  if (Status s = input.Open(level, options.record, sim)) return *s;
  Evaluator evaluator(level, run, sim);
  int64_t ran = 0;
  for (int64_t i = 0; i < frames; ++i) {
    Result<bool> stepped = input.Step(level, sim);
    if (!stepped.ok()) {
      Error e = stepped.error();
      e.message = level.path + ": run " + out.name + ": " + e.Format();
      e.loc = {};
      return e;
    }
    if (!stepped.value()) break;
    ran = i + 1;
    // the state after frame i belongs to the time at the end of the frame
    const double t = static_cast<double>(i + 1) * frameDuration;
    out.frames.push_back(sim.stats());
    AppendObjectRows(sim, i, t, out.objectsCsv);
    AppendFrameRow(sim.stats(), t, out.framesCsv);
    evaluator.AfterFrame(sim, t, out);
    if (observer) observer(out, sim);
  }
  input.Close();
  evaluator.Finish(sim, static_cast<double>(ran) * frameDuration, out);
  return out;
}

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = q * static_cast<double>(values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(rank));
  const size_t hi = std::min(values.size() - 1, lo + 1);
  return Lerp(values[lo], values[hi], rank - static_cast<double>(lo));
}

}  // namespace

bool RunResult::Passed() const {
  return std::all_of(results.begin(), results.end(),
                     [](const ExpectationResult& r) { return r.passed; });
}

bool LevelResult::Passed() const {
  return std::all_of(runs.begin(), runs.end(), [](const RunResult& r) { return r.Passed(); });
}

Result<LevelResult> RunLevel(const Level& level, const RunOptions& options,
                             const FrameObserver& observer) {
  LevelResult result;
  const std::vector<LevelRun> runs = LevelRuns(level, options.mode);
  for (const LevelRun& run : runs) {
    // only the first run is recorded, with its trace beside the video
    RunOptions runOptions = options;
    if (&run != &runs.front()) runOptions.record.clear();
    Result<RunResult> one = RunOne(level, run, runOptions, observer);
    if (!one.ok()) return one.error();
    if (!runOptions.record.empty()) {
      if (Status s = WriteTrace(one.value(), RecordingTraceDir(runOptions.record))) return *s;
    }
    if (!options.traceDir.empty()) {
      // one run writes straight into the folder; several get a folder each
      std::string dir = options.traceDir;
      if (runs.size() > 1) {
        std::string sub = one.value().name;
        std::replace(sub.begin(), sub.end(), '/', '-');
        dir += "/" + sub;
      }
      if (Status s = WriteTrace(one.value(), dir)) return *s;
    }
    result.runs.push_back(std::move(one.value()));
  }
  return result;
}

std::string RecordingTraceDir(const std::string& recordingPath) {
  std::filesystem::path p(recordingPath);
  return (p.parent_path() / (p.stem().string() + "_trace")).string();
}

Status WriteTrace(const RunResult& run, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return MakeError({dir}, "cannot create the trace folder: " + ec.message());
  for (const auto& [name, text] :
       {std::pair<std::string, const std::string*>{"objects.csv", &run.objectsCsv},
        {"frames.csv", &run.framesCsv}}) {
    const std::string path = dir + "/" + name;
    std::ofstream out(path, std::ios::binary);
    out << *text;
    if (!out) return MakeError({path}, "cannot write the trace file");
  }
  return std::nullopt;
}

std::string FormatReport(const Level& level, const LevelResult& result) {
  std::string out = "level " + level.name + " (" + level.path + ")\n";
  for (const RunResult& run : result.runs) {
    out += "  run " + run.name + ": " + std::to_string(run.frames.size()) + " frames\n";
    if (run.results.empty()) out += "    (no expectations in this run)\n";
    for (const ExpectationResult& r : run.results) {
      char line[512];
      std::snprintf(line, sizeof(line), "    %-4s  %-48s  measured %s\n",
                    r.passed ? "PASS" : "FAIL", r.text.c_str(), r.measured.c_str());
      out += line;
      if (r.expectation && !r.expectation->label.empty()) {
        out += "          (" + r.expectation->label + ")\n";
      }
      if (!r.passed && r.expectation) {
        out += "          at " + r.expectation->loc.Format() + "\n";
      }
    }
  }
  out += result.Passed() ? "  => PASS\n" : "  => FAIL\n";
  return out;
}

std::string FormatProfile(const LevelResult& result) {
  std::vector<double> sense, track, proxy, physics, total;
  for (const RunResult& run : result.runs) {
    for (const FrameStats& f : run.frames) {
      sense.push_back(f.senseMs);
      track.push_back(f.trackMs);
      proxy.push_back(f.proxyMs);
      physics.push_back(f.physicsMs);
      total.push_back(f.totalMs);
    }
  }
  std::string out =
      "  stage      median ms    p99 ms   (" + std::to_string(total.size()) + " frames)\n";
  for (const auto& [name, values] : {std::pair<const char*, std::vector<double>*>{"sense", &sense},
                                     {"track", &track},
                                     {"proxies", &proxy},
                                     {"physics", &physics},
                                     {"total", &total}}) {
    char line[128];
    std::snprintf(line, sizeof(line), "  %-9s %10.3f %9.3f\n", name, Percentile(*values, 0.5),
                  Percentile(*values, 0.99));
    out += line;
  }
  return out;
}

}  // namespace pg
