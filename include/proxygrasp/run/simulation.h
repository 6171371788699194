// The whole frame pipeline for one run of a level: synthetic camera (or a real frame), sensing,
// tracking, proxies and the layered physics. The headless runner (run/runner.h), `sense` and the
// app all step it through one FrameInput (run/frame_input.h) and write its traces with one
// TraceWriter (run/trace.h), so every input path runs the same stages in the same order.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/timer.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/level/params.h"
#include "proxygrasp/physics/layered_world.h"
#include "proxygrasp/proxies/proxy_stage.h"
#include "proxygrasp/sensing/depth_sensor.h"
#include "proxygrasp/sensing/sensor.h"
#include "proxygrasp/sensing/synthetic_camera.h"
#include "proxygrasp/tracking/tracker.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace pg {

/// Counts and per-stage times of one frame, as frames.csv records them: wall ms, or the stepping
/// thread's CPU ms when SimulationOptions::stageClock says so.
struct FrameStats {
  int64_t frame = 0;     ///< frame number from 0
  double time = 0.0;     ///< s, at the start of the frame
  int contacts = 0;      ///< current (not lifted) touching contacts (hover regions not counted)
  int merges = 0;        ///< contacts that several of the last frame's merged into (tracking)
  int splits = 0;        ///< last frame's contacts that split into several (tracking)
  int particles = 0;     ///< live particle stacks after the frame
  int created = 0;       ///< particles created this frame
  int deleted = 0;       ///< particles deleted this frame
  int bodies = 0;        ///< Box2D bodies (slices and particle bodies)
  double senseMs = 0.0;  ///< camera rendering is not included
  double trackMs = 0.0;
  double proxyMs = 0.0;
  double physicsMs = 0.0;
  double totalMs = 0.0;  ///< sensing to physics
};

/// What Simulation::Retune did with a change of parameters. Keys are "section.key".
struct RetuneReport {
  std::vector<std::string> live;     ///< changes the running stages take in place; in effect
                                     ///< when `restart` is empty
  std::vector<std::string> restart;  ///< changes only Start can make; when there are any,
                                     ///< nothing was applied, not even the live ones
};

/// Which stages a simulation runs: all of them, or sensing and tracking alone (`sense` prints the
/// tracked contacts and needs no particles or physics).
enum class RunStages { kAll, kThroughTracking };

/// How a simulation is set up beyond its level and parameters.
struct SimulationOptions {
  RunStages stages = RunStages::kAll;
  /// When the sensing parameters capture no background (background_frames = 0) and the
  /// calibration brings none, the synthetic camera's clear table is the sensor's background.
  /// Off for frames from a real camera or footage, which that background does not fit.
  bool cameraBackground = true;
  /// What FrameStats' stage times measure: wall time, or the CPU time of the thread that steps
  /// (`proxygrasp bench`; physics worker threads are not counted).
  TimerClock stageClock = TimerClock::kWall;
  /// Every sensing stage image covers the whole frame (views of the stages: `sense --preview`,
  /// the sensing view of `play`). Off, the sensor works the high-pass out only where a contact
  /// can be (Sensor::SetWholeStages); the contours are the same.
  bool wholeStages = false;
};

/// One run of a level through the pipeline.
class Simulation {
 public:
  /// Builds the camera, sensor, tracker, proxies and world from the level's objects and the run's
  /// parameters. On error nothing is kept and the Error names the level file where it can.
  MaybeError Start(const Level& level, const LevelParams& params,
                   const SimulationOptions& options = {});

  /// Adopts new parameters between frames and keeps the run's state: objects, particles, contacts,
  /// the stages' memory and the frame count stay as they are. Each parameter's description says
  /// whether a running stage takes it (Apply::kLive, through the stage's SetParams) or only a new
  /// run can (Apply::kRestart: the table, the frame rate, the layers and particle shapes, the
  /// camera's size, lens and seed, the calibration and background capture). When any restart key
  /// changed, nothing is applied and report.restart names them (Start applies everything). A value
  /// out of its range is an Error naming it ("physics.substeps must be in [1, 64] (got 0)"), and
  /// nothing changes.
  Result<RetuneReport> Retune(const LevelParams& params);

  /// One frame whose contacts are the level's script at the current time.
  MaybeError StepScript();
  /// One frame whose contacts are these shapes, drawn by the synthetic camera.
  MaybeError StepShapes(std::span<const ContactShape> shapes);
  /// One frame from a camera image (CV_8UC1 of the sensed size), or a depth frame (CV_16UC1, mm)
  /// for the depth chain (DepthSensor); errors name the frame.
  MaybeError StepImage(const cv::Mat& frame);
  /// One frame whose contours (table cm) were sensed elsewhere: tracking onwards.
  MaybeError StepContours(const ContourFrame& contours);
  /// One frame whose contacts were sensed and tracked elsewhere (a tracker speaking TUIO): their
  /// ids are kept, the tracking stage is skipped, proxies and physics run. Lifted contacts carry
  /// their last blob. In instant mode the contours are filled into the table image the instant
  /// proxies sample.
  MaybeError StepContacts(const ContactSet& contacts);

  /// The size of the camera images the sensor takes, pixels ([camera] width and height).
  cv::Size CameraSize() const { return {m_params.camera.width, m_params.camera.height}; }

  /// Frames stepped so far; the next frame's number.
  int64_t Frame() const { return m_frame; }
  /// Time at the start of the next frame, s.
  double Time() const;
  /// Length of one frame, s.
  double FrameDuration() const { return 1.0 / m_params.physics.frameRate; }

  const Level& level() const { return m_level; }
  const LevelParams& params() const { return m_params; }
  const LayeredWorld& world() const { return m_world; }
  LayeredWorld& world() { return m_world; }
  const SyntheticCamera& camera() const { return *m_camera; }
  /// The sensing stage, with the images of its filter chain for the last frame.
  const Sensor& sensor() const { return m_sensor; }
  /// The depth sensing stage, which takes the depth frames (CV_16UC1).
  const DepthSensor& depthSensor() const { return m_depthSensor; }
  /// Whether the sensor's stage images cover the whole frame from the next frame on
  /// (SimulationOptions::wholeStages).
  void SetWholeStages(bool whole) { m_sensor.SetWholeStages(whole); }

  /// The last frame's camera image, contour frame, contacts, plan and stats.
  const cv::Mat& cameraImage() const { return m_image; }
  const ContourFrame& contours() const { return m_contours; }
  const ContactSet& contacts() const { return m_contacts; }
  const ParticlePlan& plan() const { return m_plan; }
  const FrameStats& stats() const { return m_stats; }
  /// The shapes drawn into the last frame (empty for a camera image).
  const std::vector<ContactShape>& shapes() const { return m_shapes; }
  /// For each shape of the last frame, its index in the level's script (-1 when not scripted).
  const std::vector<int>& shapeScriptIndex() const { return m_shapeScript; }

  /// The script contact a tracked contact belongs to (-1 when none): the scripted shape whose
  /// outline lies nearest the contact's centroid when it first appeared.
  int ScriptContactOf(ContactId id) const;

 private:
  MaybeError Process(const cv::Mat& frame);
  // tracking onwards, once m_contours holds the frame's contours; with `tracked`, those contacts
  // instead of the tracker's
  void ProcessContours(FrameStats& stats, double senseMs, const ContactSet* tracked = nullptr);
  void AttributeContacts();
  // fills m_contours.tableImage with the blobs' contours at full contact (instant mode)
  void FillTableImage();

  Level m_level;
  LevelParams m_params;
  std::unique_ptr<SyntheticCamera> m_camera;
  Sensor m_sensor;
  DepthSensor m_depthSensor;
  Tracker m_tracker;
  ProxyStage m_proxies;
  LayeredWorld m_world;
  SimulationOptions m_options;

  int64_t m_frame = 0;
  cv::Mat m_image;
  ContourFrame m_contours;
  ContactSet m_contacts;
  ParticlePlan m_plan;
  FrameStats m_stats;
  std::vector<ContactShape> m_shapes;
  std::vector<int> m_shapeScript;
  std::vector<std::pair<ContactId, int>> m_contactScript;  // sorted by contact id
  bool m_backgroundFromCamera = false;  // the sensor's background is the camera's clear table
};

}  // namespace pg
