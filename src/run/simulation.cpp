#include "proxygrasp/run/simulation.h"

#include "proxygrasp/core/timer.h"
#include "proxygrasp/level/script.h"
#include "proxygrasp/sensing/depth_source.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pg {

MaybeError Simulation::Start(const Level& level, const LevelParams& params,
                             const SimulationOptions& options) {
  // build into fresh stages so a failed start keeps nothing half-made
  Simulation next;
  next.m_level = level;
  next.m_params = params;
  next.m_options = options;
  next.m_camera = std::make_unique<SyntheticCamera>(params.camera, params.table);
  const cv::Size size(params.camera.width, params.camera.height);
  if (MaybeError s = next.m_sensor.Configure(params.sensing, params.table, size)) {
    if (s->loc.file.empty()) s->loc.file = level.path;
    return s;
  }
  next.m_sensor.SetWholeStages(options.wholeStages);
  if (MaybeError s =
          next.m_depthSensor.Configure(params.depth, params.sensing, params.table, size)) {
    if (s->loc.file.empty()) s->loc.file = level.path;
    return s;
  }
  // the synthetic camera knows its clear table exactly: it serves as the captured background,
  // unless the sensing parameters ask to capture one from the first frames
  if (params.camera.kind == CameraKind::kDepth) {
    // The depth camera's clear table is its surface model, with the deviation its noise model
    // gives at the table's depth: disparity_noise raw steps, and the rounding to whole steps
    // (uniform over a step: 1/sqrt(12) of one) when disparity_steps is on
    if (options.cameraBackground) {
      cv::Mat surface;
      next.m_camera->Background().convertTo(surface, CV_32F);
      const double steps = std::sqrt(params.camera.disparityNoise * params.camera.disparityNoise +
                                     (params.camera.disparitySteps ? 1.0 / 12.0 : 0.0));
      const double noise = steps * KinectStepMm(10.0 * next.m_camera->cameraHeight());
      if (MaybeError s = next.m_depthSensor.SetSurface(surface, noise)) return s;
    }
  } else if (options.cameraBackground && params.sensing.backgroundFrames == 0 &&
             !next.m_sensor.HasBackground()) {
    if (MaybeError s = next.m_sensor.SetBackground(next.m_camera->Background())) return s;
    next.m_backgroundFromCamera = true;
  }
  if (MaybeError s = next.m_tracker.SetParams(params.tracking)) return s;
  if (MaybeError s = next.m_proxies.SetParams(params.proxies)) return s;
  if (MaybeError s = next.m_world.Build(params.physics, params.table, level.objects)) return s;
  *this = std::move(next);
  return std::nullopt;
}

Result<RetuneReport> Simulation::Retune(const LevelParams& params) {
  if (!m_camera) return MakeError({m_level.path}, "the simulation has not started");
  if (MaybeError s = CheckParams(params)) return *s;

  // every changed key, live or restart as its description says (Apply)
  RetuneReport report;
  LevelParams before = m_params;
  LevelParams after = params;
  const std::vector<ParamSection> old = Sections(before);
  const std::vector<ParamSection> now = Sections(after);
  for (size_t i = 0; i < old.size(); ++i) {
    const std::vector<std::string> restart = RestartKeysChanged(old[i], now[i]);
    for (const std::string& key : ChangedKeys(old[i], now[i])) {
      const bool fixed = std::find(restart.begin(), restart.end(), key) != restart.end();
      (fixed ? report.restart : report.live).push_back(old[i].name + "." + key);
    }
  }
  if (!report.restart.empty()) return report;

  // every stage takes the change in place (the fixed keys and ranges were checked above, so none
  // rejects it)
  if (MaybeError s = m_sensor.SetParams(params.sensing)) return *s;
  if (MaybeError s = m_depthSensor.SetParams(params.depth, params.sensing)) return *s;
  if (MaybeError s = m_camera->SetParams(params.camera)) return *s;
  if (MaybeError s = m_world.SetParams(params.physics)) return *s;
  if (MaybeError s = m_tracker.SetParams(params.tracking)) return *s;
  if (MaybeError s = m_proxies.SetParams(params.proxies)) return *s;
  // a background taken from the camera's clear table follows its lighting
  const bool lighting = params.camera.background != m_params.camera.background ||
                        params.camera.gradient != m_params.camera.gradient ||
                        params.camera.vignetting != m_params.camera.vignetting;
  if (lighting && m_backgroundFromCamera) {
    if (MaybeError s = m_sensor.SetBackground(m_camera->Background())) return *s;
  }
  m_params = params;
  return report;
}

double Simulation::Time() const {
  return static_cast<double>(m_frame) * FrameDuration();
}

MaybeError Simulation::StepScript() {
  m_shapeScript.clear();
  std::vector<ContactShape> shapes = ShapesAt(m_level.script, Time(), &m_shapeScript);
  m_shapes = std::move(shapes);
  m_image = m_camera->Render(m_shapes);
  return Process(m_image);
}

MaybeError Simulation::StepShapes(std::span<const ContactShape> shapes) {
  m_shapes.assign(shapes.begin(), shapes.end());
  m_shapeScript.assign(m_shapes.size(), -1);
  m_image = m_camera->Render(m_shapes);
  return Process(m_image);
}

MaybeError Simulation::StepImage(const cv::Mat& frame) {
  m_shapes.clear();
  m_shapeScript.clear();
  m_image = frame;
  return Process(m_image);
}

MaybeError Simulation::StepContours(const ContourFrame& contours) {
  m_shapes.clear();
  m_shapeScript.clear();
  m_image.release();
  m_contours = contours;
  FrameStats stats;
  stats.frame = m_frame;
  stats.time = Time();
  ProcessContours(stats, 0.0);
  return std::nullopt;
}

MaybeError Simulation::StepContacts(const ContactSet& contacts) {
  m_shapes.clear();
  m_shapeScript.clear();
  m_image.release();
  m_contours.index = m_frame;
  m_contours.time = Time();
  m_contours.blobs.clear();
  for (const Contact& c : contacts.contacts) {
    if (c.state != ContactState::kLifted) m_contours.blobs.push_back(c.blob);
  }
  m_contours.tableImage = TableImage();
  if (m_params.proxies.mode == ProxyMode::kInstant) FillTableImage();
  FrameStats stats;
  stats.frame = m_frame;
  stats.time = Time();
  ContactSet set = contacts;
  set.frame = m_frame;
  set.time = stats.time;
  ProcessContours(stats, 0.0, &set);
  return std::nullopt;
}

void Simulation::FillTableImage() {
  // full contact inside every contour, on the grid sensing would sample (SensingParams)
  TableImage& t = m_contours.tableImage;
  t.cmPerPixel = m_params.sensing.tableCmPerPixel;
  t.origin = Vec2::Zero();
  const int cols = static_cast<int>(std::ceil(m_params.table.width / t.cmPerPixel));
  const int rows = static_cast<int>(std::ceil(m_params.table.height / t.cmPerPixel));
  t.image = cv::Mat::zeros(rows, cols, CV_8UC1);
  constexpr int kShift = 4;  // sub-pixel bits of the polygon vertices
  constexpr double kScale = 1 << kShift;
  std::vector<std::vector<cv::Point>> polygons;
  for (const Blob& b : m_contours.blobs) {
    std::vector<cv::Point>& poly = polygons.emplace_back();
    for (Eigen::Index k = 0; k < b.contour.cols(); ++k) {
      // pixel (u, v) covers origin + (u + 0.5, v + 0.5) cmPerPixel: its centre is at u + 0.5
      const Vec2 p = b.contour.col(k);
      poly.emplace_back(static_cast<int>(std::lround((p.x() / t.cmPerPixel - 0.5) * kScale)),
                        static_cast<int>(std::lround((p.y() / t.cmPerPixel - 0.5) * kScale)));
    }
  }
  if (!polygons.empty()) cv::fillPoly(t.image, polygons, cv::Scalar(255), cv::LINE_8, kShift);
}

MaybeError Simulation::Process(const cv::Mat& frame) {
  FrameStats stats;
  stats.frame = m_frame;
  stats.time = Time();
  const bool instant = m_params.proxies.mode == ProxyMode::kInstant;

  // sensing: frame -> contours in table cm; depth frames through the depth chain
  Stopwatch watch(m_options.stageClock);
  const bool depth = frame.type() == CV_16UC1;
  Result<ContourFrame> sensed = depth ? m_depthSensor.Step(frame, m_frame, stats.time)
                                      : m_sensor.Step(frame, m_frame, stats.time, instant);
  if (!sensed.ok()) return sensed.error();
  m_contours = std::move(sensed.value());
  if (depth && instant) FillTableImage();
  ProcessContours(stats, watch.Ms());
  return std::nullopt;
}

void Simulation::ProcessContours(FrameStats& stats, double senseMs, const ContactSet* tracked) {
  const bool instant = m_params.proxies.mode == ProxyMode::kInstant;
  stats.senseMs = senseMs;
  Stopwatch total(m_options.stageClock);

  // tracking: stable contact ids
  Stopwatch watch(m_options.stageClock);
  // measured placement: the regions a depth camera sees above the touch band are tracked too,
  // so that hovering fingers and hands have particles at their heights (docs/proxies.md,
  // "Measured heights"); `sense` (tracking alone) tracks the touches only
  const bool trackHover = !tracked && m_options.stages == RunStages::kAll && !instant &&
                          !m_contours.hover.empty() && MeasuresHeights(m_params.proxies.placement);
  if (tracked) {
    m_contacts = *tracked;
  } else if (trackHover) {
    ContourFrame all;
    all.index = m_contours.index;
    all.time = m_contours.time;
    all.blobs.reserve(m_contours.blobs.size() + m_contours.hover.size());
    all.blobs.insert(all.blobs.end(), m_contours.blobs.begin(), m_contours.blobs.end());
    all.blobs.insert(all.blobs.end(), m_contours.hover.begin(), m_contours.hover.end());
    m_contacts = m_tracker.Step(all);
  } else {
    m_contacts = m_tracker.Step(m_contours);
  }
  stats.trackMs = watch.Ms();
  AttributeContacts();

  if (m_options.stages == RunStages::kAll) {
    // proxies: the particle plan, asking the world as it was after the last frame
    watch.Restart();
    const std::vector<ParticleFeedback> feedback = m_world.Feedback();
    m_plan =
        m_proxies.Step(m_contacts, m_world, feedback, instant ? &m_contours.tableImage : nullptr);
    stats.proxyMs = watch.Ms();

    // physics: apply the plan and advance one frame
    watch.Restart();
    m_world.Step(m_plan);
    stats.physicsMs = watch.Ms();
  }
  stats.totalMs = senseMs + total.Ms();

  for (const Contact& c : m_contacts.contacts) {
    if (c.state != ContactState::kLifted && !c.blob.hover) ++stats.contacts;
  }
  stats.merges = m_contacts.merges;
  stats.splits = m_contacts.splits;
  stats.particles = m_world.ParticleCount();
  stats.created = m_plan.created;
  stats.deleted = m_plan.deleted;
  stats.bodies = m_world.BodyCount();
  m_stats = stats;
  ++m_frame;
}

void Simulation::AttributeContacts() {
  // a new contact belongs to the scripted shape nearest its centroid and keeps it for life
  for (const Contact& c : m_contacts.contacts) {
    if (c.state != ContactState::kNew) continue;
    int best = -1;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < m_shapes.size(); ++i) {
      if (m_shapeScript[i] < 0) continue;
      // signed: negative inside, so a centroid inside a shape beats one near another's edge
      const double d = ShapeDistance(m_shapes[i], c.blob.centroid);
      if (d < bestDistance) {
        bestDistance = d;
        best = m_shapeScript[i];
      }
    }
    const auto at = std::lower_bound(m_contactScript.begin(), m_contactScript.end(),
                                     std::make_pair(c.id, std::numeric_limits<int>::min()));
    m_contactScript.insert(at, {c.id, best});
  }
}

int Simulation::ScriptContactOf(ContactId id) const {
  const auto at = std::lower_bound(m_contactScript.begin(), m_contactScript.end(),
                                   std::make_pair(id, std::numeric_limits<int>::min()));
  if (at == m_contactScript.end() || at->first != id) return -1;
  return at->second;
}

}  // namespace pg
