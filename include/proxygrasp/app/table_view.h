// The drawing of the table: one frame of a Simulation drawn top-down into a BGR image in display
// pixels with OpenCV. The window uploads it to a texture each frame; `run --video`, `play
// --screenshot` and the headless fallback write it to files. One drawing code path, pixel-testable
// without a window.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/ids.h"
#include "proxygrasp/level/level.h"
#include "proxygrasp/run/simulation.h"

#include <opencv2/core.hpp>

#include <span>
#include <string>
#include <unordered_map>
#include <vector>

namespace pg {

/// Maps table cm to display pixels through a 3x3 homography (y flips: display y points down).
class DisplayMap {
 public:
  DisplayMap() = default;
  /// A map from a table-to-display homography (Calibration::tableToDisplay).
  explicit DisplayMap(const cv::Matx33d& tableToDisplay);
  /// Fits the whole table into a display of `size` px, centred, keeping its aspect, with `margin`
  /// px free on every side.
  static DisplayMap Fit(const TableParams& table, cv::Size size, int margin = 8);

  /// A table point, cm, as a display point, px.
  cv::Point2d ToDisplay(const Vec2& table) const;
  /// A display point, px, as a table point, cm.
  Vec2 ToTable(const cv::Point2d& display) const;
  /// Display pixels per table cm around a table point (sqrt of the local Jacobian's determinant).
  double PixelsPerCm(const Vec2& table) const;
  const cv::Matx33d& matrix() const { return m_toDisplay; }

 private:
  cv::Matx33d m_toDisplay = cv::Matx33d::eye();
  cv::Matx33d m_toTable = cv::Matx33d::eye();
};

/// The display map of a level run: the calibration file's table-to-display homography when
/// sensing.calibration names one, else the table fitted into `size`. Errors name the file.
Result<DisplayMap> LevelDisplayMap(const LevelParams& params, cv::Size size);

/// What the table view draws besides objects, particles, contours and goals.
struct ViewOptions {
  bool forces = false;      ///< friction (orange) and normal (blue) force vectors on objects
  bool successors = false;  ///< a line from where each reused particle was last drawn to its target
  int layer = -1;           ///< draw only this height layer (-1: every layer)
  bool cameraImage = false;  ///< the raw camera image under the drawing
  /// The sensing view, for tuning on a real table: the window shows each filter stage of the
  /// last camera frame side by side, the contacts' outlines and ids on the camera image, and the
  /// table drawing in the first tile.
  bool sensing = false;
  bool hud = true;    ///< the heads-up line
  bool help = false;  ///< the key help overlay
};

/// Turns on the overlays named in a comma-separated list: "forces", "successors", "camera",
/// "sensing", "help", "nohud", "layer=N". Errors name the unknown word.
MaybeError ParseViewOptions(const std::string& list, ViewOptions& options);

/// Text the caller adds to the picture: frame rate, state and errors.
struct Overlay {
  double fps = 0.0;               ///< frames per second of the loop (0: not shown)
  std::string status;             ///< e.g. "paused", "recording out/rec.mkv"
  std::string error;              ///< shown in red, e.g. a failed reload's file:line:col: message
  std::vector<std::string> help;  ///< lines of the help overlay when ViewOptions::help
};

/// How far an object has come towards a goal, 0..1; exactly 1 when Goal::IsMet. Position progress
/// is the fraction of the start's distance to the zone covered, angle progress the fraction of the
/// start's angle error removed; a goal with both takes the smaller.
double GoalProgress(const Goal& goal, const Pose2& start, const Pose2& now);

/// Pixels kept free between two goal labels moved apart by SpreadLabels.
inline constexpr int kLabelGap = 6;

/// Places label boxes (display px) so that no two overlap: each box in turn keeps the place it
/// wants when that overlaps no box placed before it and lies inside the image, otherwise it takes
/// the nearest such place straight above or below, in steps of its height plus kLabelGap (below
/// first). A box with no free place anywhere keeps the place it wants.
std::vector<cv::Rect> SpreadLabels(std::span<const cv::Rect> wanted, cv::Size image);

/// The sensing view's grid in a picture of `picture` px: `count` tiles, the table drawing's first,
/// then one per sensing stage (the IR chain's kSensingStageCount, the depth chain's
/// kDepthStageCount), each of the camera's aspect, laid out to be largest below the top `top` px
/// (kept for the heads-up lines), centred. Empty when nothing fits.
std::vector<cv::Rect> SensingTiles(cv::Size picture, cv::Size camera, int top,
                                   int count = kSensingStageCount + 1);

/// Colours of the drawing (BGR), shared with tests that look for them.
namespace view_colors {
inline const cv::Scalar kOutside(12, 12, 12);     ///< outside the table
inline const cv::Scalar kTable(38, 34, 30);       ///< the table surface
inline const cv::Scalar kContour(235, 235, 235);  ///< contact contours
inline const cv::Scalar kGoal(0, 200, 255);       ///< goal zones and marks not met (amber)
inline const cv::Scalar kGoalMet(80, 220, 80);    ///< goals met (green)
inline const cv::Scalar kError(60, 60, 255);      ///< error text (red)
/// The base colour of object i; its slices are shaded from dark (bottom) to this (top).
cv::Scalar Object(int i);
/// The colour of particles whose lowest body is in `layer`.
cv::Scalar Layer(int layer);
}  // namespace view_colors

/// Draws frames of a simulation. Keeps the last frame's particle positions for successor links.
class TableView {
 public:
  /// Draws the simulation's last frame into a new BGR image of `size`.
  cv::Mat Draw(const Simulation& sim, const DisplayMap& map, cv::Size size,
               const ViewOptions& options, const Overlay& overlay = {});
  /// The same into `picture`, reusing its buffer when it has that size (the window draws every
  /// frame into one picture: a fresh 3.7 MB image a frame fragments the heap).
  void Draw(const Simulation& sim, const DisplayMap& map, cv::Size size, const ViewOptions& options,
            const Overlay& overlay, cv::Mat& picture);
  /// Forgets the last frame (after a restart).
  void Reset() { m_lastPositions.clear(); }
  /// Where the last picture shows the table drawing: the whole picture, or the sensing view's
  /// first tile.
  const cv::Rect& tableRect() const { return m_tableRect; }
  /// A point of the last picture, px, as the point of the full-size table drawing it shows (what
  /// DisplayMap::ToTable takes): the identity unless the sensing view shrank the drawing.
  cv::Point2d PictureToDisplay(const cv::Point2d& picture) const;

 private:
  std::unordered_map<ParticleId, Vec2> m_lastPositions;
  cv::Size m_size;
  cv::Rect m_tableRect;
  cv::Mat m_sensing;  // the sensing view's grid, swapped with the picture
};

}  // namespace pg
