#include "proxygrasp/bench/bench.h"

#include "proxygrasp/core/timer.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/proxies/matching.h"
#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/simulation.h"
#include "proxygrasp/sensing/depth_sensor.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#ifndef PROXYGRASP_BUILD_TYPE
#define PROXYGRASP_BUILD_TYPE "unknown"
#endif

namespace pg {

BareSensingChain::BareSensingChain(const SensingParams& params, const TableParams& table,
                                   const cv::Mat& background)
    : m_params(params), m_background(background) {
  assert(background.type() == CV_8UC1 && "the background is an 8-bit grey image");
  // the sensor's sizes in cm, in pixels of this camera
  const double pxPerCm = background.cols / table.width;
  m_sigma = params.smooth * pxPerCm;
  if (params.highpassWidth > 0.0) {
    m_highpassWidth = static_cast<int>(std::lround(params.highpassWidth * pxPerCm)) | 1;
  }
  if (params.morphology > 0) {
    const int size = 2 * params.morphology + 1;
    m_kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size));
  }
}

size_t BareSensingChain::Step(const cv::Mat& frame) {
  const SensingParams& p = m_params;
  cv::absdiff(frame, m_background, m_diff);
  // below a third of a pixel a Gaussian changes nothing (as in the sensor)
  const cv::Mat* image = &m_diff;
  if (m_sigma >= 0.3) {
    cv::GaussianBlur(m_diff, m_smooth, cv::Size(), m_sigma, m_sigma, cv::BORDER_REPLICATE);
    image = &m_smooth;
  }
  // capped high-pass: subtract the slow brightness, at most highpassCap of it
  if (m_highpassWidth > 0) {
    cv::blur(*image, m_wide, cv::Size(m_highpassWidth, m_highpassWidth), cv::Point(-1, -1),
             cv::BORDER_REPLICATE);
    cv::min(m_wide, p.highpassCap, m_wide);
    cv::subtract(*image, m_wide, m_high);
    image = &m_high;
  }
  image->convertTo(m_gained, CV_8UC1, p.gain);
  if (p.thresholdMode == ThresholdMode::kAuto) {
    const double level =
        cv::threshold(m_gained, m_binary, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
    if (level < p.autoFloor) cv::threshold(m_gained, m_binary, p.autoFloor, 255, cv::THRESH_BINARY);
  } else {
    cv::threshold(m_gained, m_binary, p.threshold, 255, cv::THRESH_BINARY);
  }
  if (!m_kernel.empty()) cv::morphologyEx(m_binary, m_binary, cv::MORPH_OPEN, m_kernel);
  // the sensor's retrieval: every component's outer border, those inside another's hole too
  cv::findContours(m_binary, m_contours, m_hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_NONE);
  return m_contours.size();
}

BareDepthChain::BareDepthChain(const cv::Mat& surfaceMm, const cv::Mat& lowMm, double highMm,
                               int morphology)
    : m_surface(surfaceMm), m_low(lowMm), m_high(surfaceMm.size(), CV_32F, cv::Scalar(highMm)) {
  if (morphology > 0) m_kernel = OpeningKernel(morphology);
}

size_t BareDepthChain::Step(const cv::Mat& depthMm) {
  depthMm.convertTo(m_float, CV_32F);
  cv::subtract(m_surface, m_float, m_height);
  cv::inRange(m_height, m_low, m_high, m_binary);
  if (!m_kernel.empty()) cv::morphologyEx(m_binary, m_binary, cv::MORPH_OPEN, m_kernel);
  cv::findContours(m_binary, m_contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  return m_contours.size();
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(p * static_cast<double>(values.size())));
  return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

namespace {

// frames of a clear table before the contacts come down, not timed: the sensor's first frame
// builds its maps
constexpr int kClearFrames = 3;
// frames whose contours the matching baseline times, at most (the exhaustive search costs ~8 ms
// per hand pair)
constexpr int kMatchFrames = 30;

// One standard scene: contacts of one kind on a grid of cells covering the table, each sweeping
// across its cell and back, with a box on every boundary between cells for them to push.
struct SceneDef {
  const char* name;
  const char* description;
  ShapeKind kind;
  double size;  // circle radius, cm; hand scale, non-dimensional
  int cols, rows;
  int stackSize;  // physics.stack_size
  int layers;     // physics.layers
};

constexpr SceneDef kScenes[] = {
    {"fingertips10_s3", "10 fingertips, particle stacks of 3", ShapeKind::kCircle, 0.8, 5, 2, 3, 8},
    {"flat_hands2_s3_k8", "2 flat hands, stacks of 3, 8 layers", ShapeKind::kHandFlat, 0.95, 2, 1,
     3, 8},
    {"five_hands4_s3", "4 five-finger hands, stacks of 3", ShapeKind::kHandFive, 0.7, 2, 2, 3, 8},
    {"flat_hands8", "8 flat hands, single particles", ShapeKind::kHandFlat, 0.55, 4, 2, 1, 8},
};

constexpr double kSweepHz = 0.5;         // back and forth across a cell, Hz
constexpr double kSweepFraction = 0.45;  // of a cell's width each side of its centre
constexpr double kBoxSize = 3.0;         // cm, width, depth and height of the boxes
constexpr double kBoxMass = 50.0;        // g

const SceneDef* FindScene(const std::string& name) {
  for (const SceneDef& s : kScenes) {
    if (name == s.name) return &s;
  }
  return nullptr;
}

// the scene's level: the default parameters, its stack size and layers, and its boxes
Result<Level> SceneLevel(const SceneDef& def) {
  const TableParams table;
  const double cellW = table.width / def.cols, cellH = table.height / def.rows;
  std::ostringstream toml;
  toml << "name = \"" << def.name << "\"\n"
       << "description = \"" << def.description << "\"\n"
       << "[physics]\nstack_size = " << def.stackSize << "\nlayers = " << def.layers << "\n";
  for (int r = 0; r < def.rows; ++r) {
    for (int c = 1; c < def.cols; ++c) {
      toml << "[[objects]]\nname = \"box" << r << "_" << c << "\"\nshape = \"box\"\n"
           << "size_x = " << kBoxSize << "\nsize_y = " << kBoxSize << "\nheight = " << kBoxSize
           << "\nmass = " << kBoxMass << "\npos = [" << c * cellW << ", " << (r + 0.5) * cellH
           << "]\n";
    }
  }
  return ParseLevel(toml.str(), std::string("bench/") + def.name + ".toml");
}

// the contacts at a frame: every contact sweeps in phase, so neighbours keep a cell apart
void SceneShapes(const SceneDef& def, int64_t frame, double frameRate,
                 std::vector<ContactShape>& shapes) {
  shapes.clear();
  if (frame < kClearFrames) return;
  const TableParams table;
  const double cellW = table.width / def.cols, cellH = table.height / def.rows;
  const double t = static_cast<double>(frame - kClearFrames) / frameRate;
  const double phase = 2.0 * kPi * kSweepHz * t;
  for (int r = 0; r < def.rows; ++r) {
    for (int c = 0; c < def.cols; ++c) {
      ContactShape s;
      s.kind = def.kind;
      if (def.kind == ShapeKind::kCircle) {
        s.radius = def.size;
      } else {
        s.scale = def.size;
      }
      s.pose.pos = Vec2((c + 0.5) * cellW + kSweepFraction * cellW * std::sin(phase),
                        (r + 0.5) * cellH + 0.1 * cellH * std::sin(0.5 * phase + r));
      s.pose.angle = 0.15 * std::sin(0.7 * phase + c);
      shapes.push_back(s);
    }
  }
}

BenchFigure Figure(const std::string& name, const std::vector<double>& ms) {
  return {name, Percentile(ms, 0.5), Percentile(ms, 0.99)};
}

BenchBaseline Baseline(const std::string& name, const std::string& scene,
                       const std::vector<double>& ours, const std::vector<double>& bare) {
  BenchBaseline b;
  b.name = name;
  b.scene = scene;
  b.oursMs = Percentile(ours, 0.5);
  b.bareMs = Percentile(bare, 0.5);
  b.ratio = b.bareMs > 0.0 ? b.oursMs / b.bareMs : 0.0;
  return b;
}

double LoadAverage() {
  std::ifstream in("/proc/loadavg");
  double load = -1.0;
  if (!(in >> load)) return -1.0;
  return load;
}

// per-frame times of one scene, every repeat together
struct SceneTimes {
  std::vector<double> sense, track, proxies, physics, total, box2d, bare;
  double contacts = 0.0, particles = 0.0, bodies = 0.0;
  // consecutive contours of the same contact, per frame, for the matching baseline
  std::vector<std::vector<std::pair<Contour, Contour>>> matchFrames;
};

// runs the pipeline over the frames once, appending to `times`
MaybeError TimePipeline(const Level& level, const std::vector<cv::Mat>& frames, bool keepContours,
                        TimerClock clock, SceneTimes& times, uint64_t* stateHash) {
  SimulationOptions options;
  options.stageClock = clock;
  Simulation sim;
  if (MaybeError e = sim.Start(level, level.params, options)) return e;
  sim.world().SetBox2DClock(clock);
  std::map<ContactId, Contour> previous;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (MaybeError e = sim.StepImage(frames[i])) return e;
    if (i < static_cast<size_t>(kClearFrames)) continue;
    const FrameStats& s = sim.stats();
    times.sense.push_back(s.senseMs);
    times.track.push_back(s.trackMs);
    times.proxies.push_back(s.proxyMs);
    times.physics.push_back(s.physicsMs);
    times.total.push_back(s.totalMs);
    times.box2d.push_back(sim.world().Box2DMs());
    times.contacts += s.contacts;
    times.particles += s.particles;
    times.bodies += s.bodies;

    // pair each current contact's contour with its last frame's
    if (!keepContours || static_cast<int>(times.matchFrames.size()) >= kMatchFrames) continue;
    std::map<ContactId, Contour> current;
    std::vector<std::pair<Contour, Contour>> pairs;
    for (const Contact& c : sim.contacts().contacts) {
      if (c.state == ContactState::kLifted || c.blob.contour.cols() < 3) continue;
      const auto prev = previous.find(c.id);
      if (prev != previous.end()) pairs.emplace_back(prev->second, c.blob.contour);
      current.emplace(c.id, c.blob.contour);
    }
    previous = std::move(current);
    if (!pairs.empty()) times.matchFrames.push_back(std::move(pairs));
  }
  if (stateHash != nullptr) {
    uint64_t h = 14695981039346656037ULL;  // FNV-1a
    auto mix = [&h](double v) {
      uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      for (int b = 0; b < 8; ++b) {
        h ^= (bits >> (8 * b)) & 0xffu;
        h *= 1099511628211ULL;
      }
    };
    for (size_t i = 0; i < level.objects.size(); ++i) {
      const ObjectState o = sim.world().Object(static_cast<ObjectId>(i));
      for (double v : {o.pose.pos.x(), o.pose.pos.y(), o.pose.angle, o.velocity.x(), o.velocity.y(),
                       o.angularVelocity}) {
        mix(v);
      }
    }
    *stateHash = h;
  }
  return std::nullopt;
}

// CPU ms per frame of matching every pair of the frame with `match`
template <typename Match>
std::vector<double> TimeMatching(const SceneTimes& times, Match match) {
  std::vector<double> ms;
  for (const auto& pairs : times.matchFrames) {
    const Stopwatch watch(TimerClock::kThreadCpu);
    size_t successors = 0;
    for (const auto& [prev, cur] : pairs) successors += match(prev, cur).successor.size();
    ms.push_back(watch.Ms());
    // every search gives each previous point its successor
    assert(successors > 0 && "a matched frame has successors");
    (void)successors;
  }
  return ms;
}

MaybeError RunScene(const SceneDef& def, const BenchOptions& options, BenchReport& report) {
  Result<Level> level = SceneLevel(def);
  if (!level.ok()) return level.error();
  if (MaybeError e = ApplyOverrides(level.value(), options.sets)) return e;
  const LevelParams& params = level.value().params;

  // render every frame beforehand, timing each as a live camera pays it: one frame at a time,
  // released before the next, so that the allocator hands its memory back; the copy kept for the
  // pipeline is made outside the timing (fresh memory for every kept frame was page faults, 0.3
  // to 0.6 ms a frame on a virtual machine, that no live frame pays)
  SyntheticCamera camera(params.camera, params.table);
  std::vector<cv::Mat> frames;
  std::vector<double> renderMs;
  std::vector<ContactShape> shapes;
  cv::Mat frame;
  for (int64_t i = 0; i < kClearFrames + options.frames; ++i) {
    SceneShapes(def, i, params.physics.frameRate, shapes);
    frame.release();
    const Stopwatch watch(TimerClock::kThreadCpu);
    frame = camera.Render(shapes);
    if (i >= kClearFrames) renderMs.push_back(watch.Ms());
    frames.push_back(frame.clone());
  }
  report.render.push_back(Figure(def.name, renderMs));

  // the pipeline, then the bare OpenCV chain on the same frames, per repeat
  SceneTimes times;
  uint64_t stateHash = 0;
  for (int r = 0; r < options.repeat; ++r) {
    if (MaybeError e = TimePipeline(level.value(), frames, r == 0, options.clock, times,
                                    r == 0 ? &stateHash : nullptr)) {
      return e;
    }
    BareSensingChain bare(params.sensing, params.table, camera.Background());
    for (size_t i = kClearFrames; i < frames.size(); ++i) {
      const Stopwatch watch(TimerClock::kThreadCpu);
      bare.Step(frames[i]);
      times.bare.push_back(watch.Ms());
    }
  }

  BenchScene scene;
  scene.name = def.name;
  scene.description = def.description;
  scene.frames = static_cast<int>(times.total.size());
  const double n = std::max(1, scene.frames);
  scene.contacts = times.contacts / n;
  scene.particles = times.particles / n;
  scene.bodies = times.bodies / n;
  scene.stages = {Figure("sense", times.sense), Figure("track", times.track),
                  Figure("proxies", times.proxies), Figure("physics", times.physics),
                  Figure("total", times.total)};
  scene.total = scene.stages.back();
  scene.stateHash = stateHash;
  report.scenes.push_back(scene);

  report.baselines.push_back(Baseline("sensing_vs_bare_opencv", def.name, times.sense, times.bare));
  report.baselines.push_back(Baseline("physics_vs_box2d", def.name, times.physics, times.box2d));
  if (!times.matchFrames.empty()) {
    // the stage's own search (the default: windowed) against the paper's exhaustive one
    const ProxyParams& proxies = params.proxies;
    const std::vector<double> ours = TimeMatching(
        times,
        [&proxies](const Contour& a, const Contour& b) { return MatchSuccessors(proxies, a, b); });
    const int window = std::clamp(proxies.window, 0, kMaxMatchWindow);
    const std::vector<double> exhaustive = TimeMatching(
        times,
        [window](const Contour& a, const Contour& b) { return MatchReference(a, b, window); });
    report.baselines.push_back(Baseline("matching_vs_exhaustive", def.name, ours, exhaustive));
  }
  return std::nullopt;
}

// a JSON string literal (names and descriptions here are plain ASCII; quotes and backslashes are
// escaped, control characters dropped)
std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) >= 0x20) {
      out += c;
    }
  }
  return out + "\"";
}

std::string Hex(uint64_t v) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "0x%016llx", static_cast<unsigned long long>(v));
  return buffer;
}

// a JSON number; a value that is not finite (never expected) is null
std::string Number(double v) {
  if (!std::isfinite(v)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

std::string FigureJson(const BenchFigure& f) {
  return "\"p50_ms\": " + Number(f.p50) + ", \"p99_ms\": " + Number(f.p99);
}

}  // namespace

std::vector<std::string> BenchSceneNames() {
  std::vector<std::string> names;
  for (const SceneDef& s : kScenes) names.emplace_back(s.name);
  return names;
}

BenchMachine DescribeBenchMachine() {
  BenchMachine m;
  m.cpu = "unknown";
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const size_t colon = line.find(':');
    const size_t value =
        colon == std::string::npos ? colon : line.find_first_not_of(" \t", colon + 1);
    if (value != std::string::npos) m.cpu = line.substr(value);
    break;
  }
  m.cores = static_cast<int>(std::thread::hardware_concurrency());
#if defined(__clang__)
  m.compiler = "clang " __clang_version__;
#elif defined(__GNUC__)
  m.compiler = "gcc " __VERSION__;
#else
  m.compiler = "unknown";
#endif
  m.buildType = PROXYGRASP_BUILD_TYPE;
  m.opencv = CV_VERSION;
  m.loadStart = m.loadEnd = LoadAverage();
  return m;
}

namespace {

// The depth scene: frames rendered first (not timed), then DepthSensor::Step and the bare chain
// on the same frames, per repeat. The table tilts by 6 mm across the image; fingertips (r 0.8 cm,
// 14 mm thick) on a 5 x 2 grid and two palms (r 4 cm, top 5 cm up) sweep as the standard scenes'
// contacts do (0.5 Hz, +-45% of a cell).
MaybeError RunDepthScene(const BenchOptions& options, BenchReport& report) {
  LevelParams params;
  if (MaybeError s = ApplyOverrides(params, options.sets)) return s;
  const cv::Size size(640, 480);
  const double pxPerCm = size.width / params.table.width;
  const double fps = params.physics.frameRate;
  cv::Mat plane(size, CV_32F);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) plane.at<float>(v, u) = 1000.0f + 0.01f * u;
  cv::RNG rng(43);
  cv::Mat noise(size, CV_32F), mm;
  auto render = [&](int64_t i, bool clear, cv::Mat& out) {
    mm = plane.clone();
    if (!clear) {
      const double t = static_cast<double>(i) / fps;
      const double sweep = 0.45 * std::sin(2.0 * kPi * 0.5 * t);
      for (int k = 0; k < 10; ++k) {
        const double cellW = params.table.width / 5, cellH = params.table.height / 2;
        const double x = (k % 5 + 0.5 + sweep) * cellW, y = (k / 5 + 0.5) * cellH;
        cv::circle(mm, cv::Point2d(x * pxPerCm, (params.table.height - y) * pxPerCm),
                   static_cast<int>(0.8 * pxPerCm), cv::Scalar(1000.0 - 14.0), cv::FILLED);
      }
      for (int k = 0; k < 2; ++k) {
        const double cellW = params.table.width / 2;
        const double x = (k + 0.5 - sweep) * cellW, y = 0.5 * params.table.height;
        cv::circle(mm, cv::Point2d(x * pxPerCm, (params.table.height - y) * pxPerCm),
                   static_cast<int>(4.0 * pxPerCm), cv::Scalar(1000.0 - 50.0), cv::FILLED);
      }
    }
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.5);
    mm += noise;
    mm.convertTo(out, CV_16UC1);
  };
  const int learn = params.depth.surfaceFrames;
  std::vector<cv::Mat> frames(static_cast<size_t>(learn + options.frames));
  for (size_t i = 0; i < frames.size(); ++i)
    render(static_cast<int64_t>(i), static_cast<int>(i) < learn, frames[i]);

  std::vector<double> ours, bare;
  for (int r = 0; r < options.repeat; ++r) {
    DepthSensor sensor;
    if (MaybeError s = sensor.Configure(params.depth, params.sensing, params.table, size)) return s;
    for (size_t i = 0; i < frames.size(); ++i) {
      const Stopwatch watch(options.clock);
      Result<ContourFrame> f =
          sensor.Step(frames[i], static_cast<int64_t>(i), static_cast<double>(i) / fps);
      const double ms = watch.Ms();
      if (!f.ok()) return f.error();
      if (static_cast<int>(i) >= learn) ours.push_back(ms);
    }
    // the bare chain on the surface the sensor learned; its band's lower edge per pixel is the
    // sensor's noise edge, max(touch_low, noise_factor x max(deviation, noise_floor (z / 1 m)^2)),
    // as the same touch mask needs it (at 1 m the noise edge, 6 mm, is above touch_low's 5)
    const cv::Mat& surface = sensor.Surface();
    const float lowMm = static_cast<float>(10.0 * params.depth.touchLow);
    const float factor = static_cast<float>(params.depth.noiseFactor);
    const float floorPerMm2 = static_cast<float>(params.depth.noiseFloor * 1e-6);
    cv::Mat low(size, CV_32F);
    for (int v = 0; v < size.height; ++v) {
      for (int u = 0; u < size.width; ++u) {
        const float z = surface.at<float>(v, u), noise = sensor.SurfaceNoise().at<float>(v, u);
        low.at<float>(v, u) = std::max(lowMm, factor * std::max(noise, floorPerMm2 * z * z));
      }
    }
    BareDepthChain chain(surface, low, 10.0 * params.depth.touchHigh, params.sensing.morphology);
    for (size_t i = static_cast<size_t>(learn); i < frames.size(); ++i) {
      const Stopwatch watch(options.clock);
      chain.Step(frames[i]);
      bare.push_back(watch.Ms());
    }
  }
  report.baselines.push_back(Baseline("depth_vs_bare_opencv", kDepthBenchScene, ours, bare));
  return std::nullopt;
}

}  // namespace

Result<BenchReport> RunBench(const BenchOptions& options) {
  // check every option before anything runs
  if (options.frames < 1) {
    return MakeError({}, "--frames must be >= 1 (got " + std::to_string(options.frames) + ")");
  }
  if (options.repeat < 1) {
    return MakeError({}, "--repeat must be >= 1 (got " + std::to_string(options.repeat) + ")");
  }
  std::vector<const SceneDef*> scenes;
  bool depth = options.scenes.empty();
  for (const std::string& name : options.scenes.empty() ? BenchSceneNames() : options.scenes) {
    if (name == kDepthBenchScene) {
      depth = true;
      continue;
    }
    const SceneDef* def = FindScene(name);
    if (def == nullptr) {
      std::string known;
      for (const std::string& n : BenchSceneNames()) known += (known.empty() ? "" : ", ") + n;
      known += std::string(", ") + kDepthBenchScene;
      return MakeError({}, "--scenes: unknown scene '" + name + "' (scenes: " + known + ")");
    }
    scenes.push_back(def);
  }

  // one core: OpenCV runs every function on the calling thread, as the stage times assume
  const int threads = cv::getNumThreads();
  cv::setNumThreads(0);
  BenchReport report;
  report.machine = DescribeBenchMachine();
  report.frames = options.frames;
  report.repeat = options.repeat;
  report.clock = options.clock;
  report.sets = options.sets;
  MaybeError failed;
  for (const SceneDef* def : scenes) {
    failed = RunScene(*def, options, report);
    if (failed) break;
  }
  if (!failed && depth) failed = RunDepthScene(options, report);
  cv::setNumThreads(threads);
  if (failed) return *failed;
  report.machine.loadEnd = LoadAverage();
  return report;
}

std::string BenchJson(const BenchReport& report) {
  const BenchMachine& m = report.machine;
  std::ostringstream out;
  out << "{\n  \"machine\": {\"cpu\": " << Quote(m.cpu) << ", \"cores\": " << m.cores
      << ", \"compiler\": " << Quote(m.compiler) << ", \"build_type\": " << Quote(m.buildType)
      << ", \"opencv\": " << Quote(m.opencv) << ", \"load_start\": " << Number(m.loadStart)
      << ", \"load_end\": " << Number(m.loadEnd) << "},\n";
  out << "  \"frames\": " << report.frames << ",\n  \"repeat\": " << report.repeat << ",\n";
  out << "  \"clock\": \"" << (report.clock == TimerClock::kWall ? "wall" : "thread_cpu")
      << "\",\n  \"sets\": [";
  for (size_t i = 0; i < report.sets.size(); ++i) out << (i ? ", " : "") << Quote(report.sets[i]);
  out << "],\n";

  out << "  \"scenes\": [";
  for (size_t i = 0; i < report.scenes.size(); ++i) {
    const BenchScene& s = report.scenes[i];
    out << (i ? ",\n" : "\n") << "    {\"name\": " << Quote(s.name)
        << ", \"description\": " << Quote(s.description) << ", \"frames\": " << s.frames
        << ", \"contacts\": " << Number(s.contacts) << ", \"particles\": " << Number(s.particles)
        << ", \"bodies\": " << Number(s.bodies) << ", \"state_hash\": " << Quote(Hex(s.stateHash))
        << ", " << FigureJson(s.total) << ",\n     \"stages\": {";
    for (size_t k = 0; k < s.stages.size(); ++k) {
      out << (k ? ", " : "") << Quote(s.stages[k].name) << ": {" << FigureJson(s.stages[k]) << "}";
    }
    out << "}}";
  }
  out << "\n  ],\n  \"render\": [";
  for (size_t i = 0; i < report.render.size(); ++i) {
    out << (i ? ",\n" : "\n") << "    {\"name\": " << Quote(report.render[i].name) << ", "
        << FigureJson(report.render[i]) << "}";
  }
  out << "\n  ],\n  \"baselines\": [";
  for (size_t i = 0; i < report.baselines.size(); ++i) {
    const BenchBaseline& b = report.baselines[i];
    out << (i ? ",\n" : "\n") << "    {\"name\": " << Quote(b.name)
        << ", \"scene\": " << Quote(b.scene) << ", \"ours_ms\": " << Number(b.oursMs)
        << ", \"bare_ms\": " << Number(b.bareMs) << ", \"ratio\": " << Number(b.ratio) << "}";
  }
  out << "\n  ]\n}\n";
  return out.str();
}

std::string FormatBench(const BenchReport& report) {
  const BenchMachine& m = report.machine;
  std::ostringstream out;
  char line[256];
  out << "machine: " << m.cpu << ", " << m.cores << " cores, " << m.compiler << ", " << m.buildType
      << ", OpenCV " << m.opencv << "\n";
  std::snprintf(line, sizeof line, "load average: %.2f at the start, %.2f at the end\n",
                m.loadStart, m.loadEnd);
  out << line;
  out << report.frames << " frames x " << report.repeat << " repeats per scene; "
      << (report.clock == TimerClock::kWall ? "wall" : "CPU")
      << " ms per frame of the stepping thread, median / p99\n";
  for (const std::string& set : report.sets) out << "--set " << set << "\n";
  out << "\n";

  std::snprintf(line, sizeof line, "%-18s %8s %15s %15s %15s %15s %15s\n", "scene", "contacts",
                "sense", "track", "proxies", "physics", "total");
  out << line;
  for (const BenchScene& s : report.scenes) {
    std::snprintf(line, sizeof line, "%-18s %8.1f", s.name.c_str(), s.contacts);
    out << line;
    for (const BenchFigure& f : s.stages) {
      std::snprintf(line, sizeof line, " %7.3f/%7.3f", f.p50, f.p99);
      out << line;
    }
    out << "\n";
  }
  out << "state after the last frame (equal across runs = bit-identical):";
  for (const BenchScene& s : report.scenes) out << " " << s.name << " " << Hex(s.stateHash);
  out << "\n";

  out << "\nrendering one camera frame (not in the stage times)\n";
  for (const BenchFigure& f : report.render) {
    std::snprintf(line, sizeof line, "%-18s %7.3f/%7.3f\n", f.name.c_str(), f.p50, f.p99);
    out << line;
  }

  out << "\nbaselines, median ms per frame on the same frames\n";
  std::snprintf(line, sizeof line, "%-24s %-18s %9s %9s %7s\n", "baseline", "scene", "ours", "bare",
                "ratio");
  out << line;
  for (const BenchBaseline& b : report.baselines) {
    std::snprintf(line, sizeof line, "%-24s %-18s %9.3f %9.3f %6.2fx\n", b.name.c_str(),
                  b.scene.c_str(), b.oursMs, b.bareMs, b.ratio);
    out << line;
  }
  return out.str();
}

}  // namespace pg
