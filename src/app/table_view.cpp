#include "proxygrasp/app/table_view.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/preview.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>

namespace pg {

namespace {

constexpr int kShift = 4;  // fixed-point bits of polygon vertices, for sub-pixel antialiasing
constexpr double kShiftScale = 1 << kShift;

cv::Point Fixed(const cv::Point2d& p) {
  return {static_cast<int>(std::lround(p.x * kShiftScale)),
          static_cast<int>(std::lround(p.y * kShiftScale))};
}

cv::Point Round(const cv::Point2d& p) {
  return {static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y))};
}

std::string Format(const char* format, double a, double b = 0, double c = 0, double d = 0,
                   double e = 0) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), format, a, b, c, d, e);
  return buffer;
}

// table points of a contour (in the pose's local frame) as fixed-point display points
std::vector<cv::Point> ToDisplay(const Contour& c, const Pose2& pose, const DisplayMap& map) {
  std::vector<cv::Point> points;
  points.reserve(static_cast<size_t>(c.cols()));
  for (int i = 0; i < c.cols(); ++i) points.push_back(Fixed(map.ToDisplay(pose.Apply(c.col(i)))));
  return points;
}

// Hovering hands as shadows on the table (Hilliges et al., UIST 2009): each region a depth camera
// sees above the touch band darkens what lies under it, darker and sharper the lower it is, so a
// user sees where a hand will land before it does. Opacity falls from kShadowNear at the table
// to kShadowFar at kShadowFade; the penumbra (blur deviation) grows as kShadowSpread times the
// height, as a broad light's does.
constexpr double kShadowNear = 0.6;
constexpr double kShadowFar = 0.1;
constexpr double kShadowFade = 30.0;  // cm
constexpr double kShadowSpread = 0.15;

void DrawHoverShadows(const std::vector<Blob>& hover, const DisplayMap& map, cv::Mat& img) {
  const cv::Rect whole(0, 0, img.cols, img.rows);
  for (const Blob& b : hover) {
    if (b.contour.cols() < 3) continue;
    const double h = std::max(0.0, b.MeanHeight().value_or(kShadowFade));
    const double opacity = std::clamp(kShadowNear + (kShadowFar - kShadowNear) * h / kShadowFade,
                                      kShadowFar, kShadowNear);
    const double sigma = std::max(0.5, kShadowSpread * h * map.PixelsPerCm(b.centroid));
    std::vector<cv::Point> poly = ToDisplay(b.contour, Pose2{}, map);
    cv::Rect box = cv::boundingRect(poly);
    box = cv::Rect(box.x >> kShift, box.y >> kShift, (box.width >> kShift) + 2,
                   (box.height >> kShift) + 2);
    const int reach = static_cast<int>(std::ceil(3.0 * sigma));
    box = cv::Rect(box.x - reach, box.y - reach, box.width + 2 * reach, box.height + 2 * reach) &
          whole;
    if (box.empty()) continue;
    for (cv::Point& q : poly) q -= cv::Point(box.x << kShift, box.y << kShift);
    cv::Mat mask = cv::Mat::zeros(box.size(), CV_32F);
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(opacity), cv::LINE_AA,
                 kShift);
    cv::GaussianBlur(mask, mask, cv::Size(0, 0), sigma);
    cv::Mat roi = img(box);
    for (int y = 0; y < roi.rows; ++y) {
      const float* m = mask.ptr<float>(y);
      cv::Vec3b* px = roi.ptr<cv::Vec3b>(y);
      for (int x = 0; x < roi.cols; ++x) {
        const float keep = 1.0f - m[x];
        for (int c = 0; c < 3; ++c) px[x][c] = cv::saturate_cast<uchar>(px[x][c] * keep);
      }
    }
  }
}

Contour RegionOutline(const Region& region) {
  if (region.kind == Region::Kind::kRect) {
    Contour c(2, 4);
    c << region.min.x(), region.max.x(), region.max.x(), region.min.x(), region.min.y(),
        region.min.y(), region.max.y(), region.max.y();
    return c;
  }
  constexpr int kSides = 64;
  Contour c(2, kSides);
  for (int i = 0; i < kSides; ++i) {
    const double a = 2.0 * kPi * i / kSides;
    c.col(i) = region.center + region.radius * Vec2(std::cos(a), std::sin(a));
  }
  return c;
}

// distance from p to a region, 0 inside, cm
double DistanceToRegion(const Region& region, const Vec2& p) {
  if (region.kind == Region::Kind::kCircle)
    return std::max(0.0, (p - region.center).norm() - region.radius);
  const double dx = std::max({region.min.x() - p.x(), 0.0, p.x() - region.max.x()});
  const double dy = std::max({region.min.y() - p.y(), 0.0, p.y() - region.max.y()});
  return std::hypot(dx, dy);
}

Vec2 RegionCenter(const Region& region) {
  return region.kind == Region::Kind::kCircle ? region.center : 0.5 * (region.min + region.max);
}

double Fraction(double startError, double nowError, double tolerance) {
  if (nowError <= tolerance) return 1.0;
  if (startError <= tolerance) return 0.0;
  return std::clamp(1.0 - (nowError - tolerance) / (startError - tolerance), 0.0, 0.99);
}

void Text(cv::Mat& img, const std::string& text, cv::Point at, double scale, const cv::Scalar& c) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, c, 1, cv::LINE_AA);
}

// the size of TextBox's box for these lines, px (empty for none)
cv::Size TextBoxSize(const std::vector<std::pair<std::string, cv::Scalar>>& lines, double scale) {
  if (lines.empty()) return {};
  int width = 0;
  int lineHeight = 0;
  for (const auto& [text, color] : lines) {
    int baseline = 0;
    const cv::Size s = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
    width = std::max(width, s.width);
    lineHeight = std::max(lineHeight, s.height + baseline + 4);
  }
  return {width + 12, lineHeight * static_cast<int>(lines.size()) + 8};
}

// lines of text on a dark box, top-left at `at`; returns the y below the box
int TextBox(cv::Mat& img, const std::vector<std::pair<std::string, cv::Scalar>>& lines,
            cv::Point at, double scale) {
  if (lines.empty()) return at.y;
  const cv::Rect box(at, TextBoxSize(lines, scale));
  const int lineHeight = (box.height - 8) / static_cast<int>(lines.size());
  cv::Mat roi = img(box & cv::Rect(0, 0, img.cols, img.rows));
  roi *= 0.35;
  int y = at.y + 4 + lineHeight - 6;
  for (const auto& [text, color] : lines) {
    Text(img, text, {at.x + 6, y}, scale, color);
    y += lineHeight;
  }
  return box.y + box.height;
}

// splits long text into lines of at most `width` characters at spaces
std::vector<std::string> Wrap(const std::string& text, size_t width) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end - start > width) {
      const size_t space = text.rfind(' ', start + width);
      end = (space != std::string::npos && space > start) ? space : start + width;
    }
    lines.push_back(text.substr(start, end - start));
    start = end;
    while (start < text.size() && (text[start] == ' ' || text[start] == '\n')) ++start;
  }
  return lines;
}

void Arrow(cv::Mat& img, const cv::Point2d& from, const Vec2& displayVector, const cv::Scalar& c) {
  if (displayVector.norm() < 2.0) return;
  const cv::Point2d to(from.x + displayVector.x(), from.y + displayVector.y());
  cv::arrowedLine(img, Fixed(from), Fixed(to), c, 2, cv::LINE_AA, kShift, 0.2);
}

// The sensing view: the table drawing and the sensing preview's tiles (the camera image with the
// contacts' outlines and ids, then each filter stage) in the grid of SensingTiles, below the
// heads-up lines (`top` px), drawn into `out`. `tableRect` becomes where the table drawing lies.
// False (nothing drawn) before the first camera frame: the table drawing shows alone.
bool SensingView(const Simulation& sim, const cv::Mat& table, int top, cv::Rect& tableRect,
                 cv::Mat& out) {
  // a depth frame (the depth camera's or a depth source's) shows the depth chain's stages
  const bool depth = sim.cameraImage().type() == CV_16UC1;
  const cv::Mat& camera = depth ? sim.depthSensor().StageImage(DepthStage::kDepth)
                                : sim.sensor().StageImage(SensingStage::kCamera);
  if (camera.empty()) return false;
  const int stages = depth ? kDepthStageCount : kSensingStageCount;
  const std::vector<cv::Rect> tiles = SensingTiles(table.size(), camera.size(), top, stages + 1);
  if (tiles.empty()) return false;
  std::vector<PreviewContact> shown;
  for (const Contact& c : sim.contacts().contacts)
    if (c.state != ContactState::kLifted) shown.push_back({&c.blob, static_cast<int>(c.id)});
  const cv::Size tile = tiles[0].size();
  // the preview's tiles at that size in one row, cut apart below
  const double scale = static_cast<double>(tile.width) / camera.cols;
  const cv::Mat row =
      depth ? DepthPreview(sim.depthSensor(), shown, sim.contours().hover, stages, scale)
            : SensingPreview(sim.sensor(), shown, stages, scale);
  if (row.empty()) return false;
  const cv::Size cut(row.cols / stages, row.rows);
  out.create(table.size(), CV_8UC3);
  out.setTo(view_colors::kOutside);

  // the table drawing, its aspect kept inside the first tile
  {
    const double s = std::min(static_cast<double>(tile.width) / table.cols,
                              static_cast<double>(tile.height) / table.rows);
    const cv::Size fit(std::max(1, static_cast<int>(table.cols * s)),
                       std::max(1, static_cast<int>(table.rows * s)));
    tableRect = cv::Rect(tiles[0].x + (tile.width - fit.width) / 2,
                         tiles[0].y + (tile.height - fit.height) / 2, fit.width, fit.height);
    cv::resize(table, out(tableRect), fit, 0, 0, cv::INTER_AREA);
  }
  // then the preview's tiles in chain order (the preview rounds its tile size: the common part)
  const cv::Size common(std::min(cut.width, tile.width), std::min(cut.height, tile.height));
  for (int k = 0; k < stages; ++k) {
    const cv::Rect at = tiles[static_cast<size_t>(k) + 1];
    row(cv::Rect(k * cut.width, 0, common.width, common.height))
        .copyTo(out(cv::Rect(at.x, at.y, common.width, common.height)));
  }
  return true;
}

}  // namespace

std::vector<cv::Rect> SensingTiles(cv::Size picture, cv::Size camera, int top, int count) {
  const int height = picture.height - std::max(0, top);
  if (camera.width <= 0 || camera.height <= 0 || picture.width <= 0 || height <= 0 || count < 1)
    return {};
  // the column count that gives the largest tiles
  int columns = 1;
  double scale = 0.0;
  for (int c = 1; c <= count; ++c) {
    const int rows = (count + c - 1) / c;
    const double s = std::min(static_cast<double>(picture.width) / (c * camera.width),
                              static_cast<double>(height) / (rows * camera.height));
    if (s > scale) {
      scale = s;
      columns = c;
    }
  }
  const int rows = (count + columns - 1) / columns;
  const cv::Size tile(static_cast<int>(camera.width * scale),
                      static_cast<int>(camera.height * scale));
  if (tile.width < 1 || tile.height < 1) return {};
  const cv::Point origin((picture.width - columns * tile.width) / 2,
                         std::max(0, top) + (height - rows * tile.height) / 2);
  std::vector<cv::Rect> tiles;
  for (int i = 0; i < count; ++i)
    tiles.emplace_back(origin.x + (i % columns) * tile.width,
                       origin.y + (i / columns) * tile.height, tile.width, tile.height);
  return tiles;
}

cv::Point2d TableView::PictureToDisplay(const cv::Point2d& picture) const {
  if (m_tableRect.width <= 0 || m_tableRect.height <= 0 || m_size.width <= 0) return picture;
  return {(picture.x - m_tableRect.x) * m_size.width / m_tableRect.width,
          (picture.y - m_tableRect.y) * m_size.height / m_tableRect.height};
}

DisplayMap::DisplayMap(const cv::Matx33d& tableToDisplay)
    : m_toDisplay(tableToDisplay), m_toTable(tableToDisplay.inv()) {}

DisplayMap DisplayMap::Fit(const TableParams& table, cv::Size size, int margin) {
  const double w = std::max(1, size.width - 2 * margin);
  const double h = std::max(1, size.height - 2 * margin);
  const double scale = std::min(w / table.width, h / table.height);
  const double left = 0.5 * (size.width - scale * table.width);
  const double top = 0.5 * (size.height - scale * table.height);
  // x right, y flipped: table y = height is the display's top
  return DisplayMap(cv::Matx33d(scale, 0, left, 0, -scale, top + scale * table.height, 0, 0, 1));
}

cv::Point2d DisplayMap::ToDisplay(const Vec2& table) const {
  const cv::Vec3d p = m_toDisplay * cv::Vec3d(table.x(), table.y(), 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}

Vec2 DisplayMap::ToTable(const cv::Point2d& display) const {
  const cv::Vec3d p = m_toTable * cv::Vec3d(display.x, display.y, 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}

double DisplayMap::PixelsPerCm(const Vec2& table) const {
  // finite differences over 1 cm are exact enough for a homography's slowly varying Jacobian
  const cv::Point2d o = ToDisplay(table);
  const cv::Point2d x = ToDisplay(table + Vec2(1, 0));
  const cv::Point2d y = ToDisplay(table + Vec2(0, 1));
  const double det = (x.x - o.x) * (y.y - o.y) - (x.y - o.y) * (y.x - o.x);
  return std::sqrt(std::abs(det));
}

Result<DisplayMap> LevelDisplayMap(const LevelParams& params, cv::Size size) {
  if (params.sensing.calibration.empty()) return DisplayMap::Fit(params.table, size);
  Result<Calibration> calibration = LoadCalibration(params.sensing.calibration);
  if (!calibration.ok()) return calibration.error();
  return DisplayMap(calibration.value().tableToDisplay);
}

MaybeError ParseViewOptions(const std::string& list, ViewOptions& options) {
  size_t start = 0;
  while (start <= list.size()) {
    size_t end = list.find(',', start);
    if (end == std::string::npos) end = list.size();
    const std::string word = list.substr(start, end - start);
    start = end + 1;
    if (word.empty()) continue;
    if (word == "forces") {
      options.forces = true;
    } else if (word == "successors") {
      options.successors = true;
    } else if (word == "camera") {
      options.cameraImage = true;
    } else if (word == "sensing") {
      options.sensing = true;
    } else if (word == "help") {
      options.help = true;
    } else if (word == "nohud") {
      options.hud = false;
    } else if (word.rfind("layer=", 0) == 0) {
      char* rest = nullptr;
      const long layer = std::strtol(word.c_str() + 6, &rest, 10);
      if (rest == word.c_str() + 6 || *rest != '\0' || layer < 0 || layer > 64)
        return MakeError({}, "'" + word + "': the layer must be a number from 0");
      options.layer = static_cast<int>(layer);
    } else {
      return MakeError(
          {}, "unknown view '" + word +
                  "' (expected forces, successors, camera, sensing, help, nohud or layer=N)");
    }
  }
  return std::nullopt;
}

std::vector<cv::Rect> SpreadLabels(std::span<const cv::Rect> wanted, cv::Size image) {
  const cv::Rect picture(0, 0, image.width, image.height);
  std::vector<cv::Rect> placed;
  placed.reserve(wanted.size());
  for (const cv::Rect& want : wanted) {
    // candidates one box height (and a gap) apart: where it wants to be, then below, above,
    // two below, ...; the first inside the picture that overlaps no placed box wins
    const int step = want.height + kLabelGap;
    const int tries = 2 * (image.height / std::max(step, 1) + 1);
    std::optional<cv::Rect> free;
    for (int k = 0; k <= tries && !free; ++k) {
      const int n = (k + 1) / 2 * (k % 2 == 1 ? 1 : -1);
      const cv::Rect r = want + cv::Point(0, n * step);
      if ((r & picture) != r) continue;
      const bool clear = std::none_of(placed.begin(), placed.end(),
                                      [&r](const cv::Rect& p) { return (r & p).area() > 0; });
      if (clear) free = r;
    }
    // no free place (more labels than fit): it stays where it wants to be
    placed.push_back(free.value_or(want));
  }
  return placed;
}

double GoalProgress(const Goal& goal, const Pose2& start, const Pose2& now) {
  if (goal.IsMet(now)) return 1.0;
  double progress = 1.0;
  if (goal.zone) {
    progress = std::min(progress, Fraction(DistanceToRegion(*goal.zone, start.pos),
                                           DistanceToRegion(*goal.zone, now.pos), 0.0));
  }
  if (goal.angle) {
    const double startError = std::abs(WrapAngle(start.angle - *goal.angle));
    const double nowError = std::abs(WrapAngle(now.angle - *goal.angle));
    progress = std::min(progress, Fraction(startError, nowError, goal.tolerance));
  }
  // not met: never report a full bar
  return std::min(progress, 0.99);
}

namespace view_colors {

cv::Scalar Object(int i) {
  static const cv::Scalar kPalette[] = {{230, 150, 70},  {90, 120, 235}, {120, 200, 120},
                                        {200, 110, 200}, {80, 200, 220}, {200, 200, 90}};
  return kPalette[static_cast<size_t>(i) % std::size(kPalette)];
}

cv::Scalar Layer(int layer) {
  // a hue wheel: layer 0 cyan, then green, yellow, ... so stacked bases read apart
  static const cv::Scalar kPalette[] = {{255, 230, 60},  {90, 255, 90},  {40, 230, 255},
                                        {60, 140, 255},  {200, 90, 255}, {255, 120, 160},
                                        {255, 255, 255}, {150, 150, 150}};
  return kPalette[static_cast<size_t>(std::max(0, layer)) % std::size(kPalette)];
}

}  // namespace view_colors

cv::Mat TableView::Draw(const Simulation& sim, const DisplayMap& map, cv::Size size,
                        const ViewOptions& options, const Overlay& overlay) {
  cv::Mat picture;
  Draw(sim, map, size, options, overlay, picture);
  return picture;
}

void TableView::Draw(const Simulation& sim, const DisplayMap& map, cv::Size size,
                     const ViewOptions& options, const Overlay& overlay, cv::Mat& picture) {
  namespace c = view_colors;
  picture.create(size, CV_8UC3);
  picture.setTo(c::kOutside);
  cv::Mat& img = picture;
  const LevelParams& params = sim.params();
  const LayeredWorld& world = sim.world();
  const double textScale = std::clamp(size.width / 2200.0, 0.35, 0.8);

  // the table surface
  {
    const TableParams& t = params.table;
    Contour corners(2, 4);
    corners << 0, t.width, t.width, 0, 0, 0, t.height, t.height;
    const std::vector<cv::Point> quad = ToDisplay(corners, Pose2{}, map);
    cv::fillConvexPoly(img, quad, c::kTable, cv::LINE_AA, kShift);
  }

  // the raw camera image, mapped camera -> table -> display (lens distortion left in)
  if (options.cameraImage && !sim.cameraImage().empty()) {
    const cv::Matx33d toDisplay = map.matrix() * sim.camera().model().cameraToTable;
    cv::Mat warped;
    cv::warpPerspective(sim.cameraImage(), warped, toDisplay, size, cv::INTER_LINEAR,
                        cv::BORDER_CONSTANT, 0);
    cv::Mat bgr;
    cv::cvtColor(warped, bgr, cv::COLOR_GRAY2BGR);
    cv::addWeighted(img, 0.4, bgr, 0.8, 0.0, img);
  }

  // goal zones under the objects
  for (const Goal& goal : sim.level().goals) {
    if (!goal.zone) continue;
    int index = -1;
    for (int i = 0; i < world.ObjectCount(); ++i)
      if (world.Object(i).name == goal.object) index = i;
    const bool met = index >= 0 && goal.IsMet(world.Object(index).pose);
    const std::vector<cv::Point> zone = ToDisplay(RegionOutline(*goal.zone), Pose2{}, map);
    cv::polylines(img, zone, true, met ? c::kGoalMet : c::kGoal, 2, cv::LINE_AA, kShift);
  }

  // objects: slices from the lowest up, lighter with height
  for (int i = 0; i < world.ObjectCount(); ++i) {
    const ObjectState state = world.Object(i);
    const std::vector<SliceOutline> slices = world.Slices(i);
    const cv::Scalar base = c::Object(i);
    const int layers = std::max(1, state.layerCount);
    std::vector<cv::Point> top;
    for (const SliceOutline& slice : slices) {
      if (options.layer >= 0 && slice.layer != options.layer) continue;
      const double shade = 0.35 + 0.65 * (slice.layer + 1) / layers;
      const std::vector<cv::Point> poly = ToDisplay(slice.outline, state.pose, map);
      cv::fillPoly(img, std::vector<std::vector<cv::Point>>{poly}, base * shade, cv::LINE_AA,
                   kShift);
      top = poly;
    }
    if (top.empty()) continue;
    const cv::Scalar edge = state.held ? cv::Scalar(255, 255, 255) : base * 0.6;
    cv::polylines(img, top, true, edge, state.held ? 2 : 1, cv::LINE_AA, kShift);
    // a tick along the local x axis shows the object's turn
    const double ppcm = map.PixelsPerCm(state.pose.pos);
    const Vec2 tip = state.pose.Apply(Vec2(std::min(2.0, 24.0 / std::max(ppcm, 1e-6)), 0));
    cv::line(img, Fixed(map.ToDisplay(state.pose.pos)), Fixed(map.ToDisplay(tip)), base * 0.3, 2,
             cv::LINE_AA, kShift);
  }

  // hovering hands (a depth camera) as shadows over the table and the objects
  DrawHoverShadows(sim.contours().hover, map, img);

  // angle goals: a mark at the target angle around the object; every goal's label and progress
  // bar are laid out here and drawn once none overlaps another
  struct GoalLabel {
    std::string text;
    cv::Scalar color;
    double progress = 0.0;
    int textHeight = 0;  // px above the baseline
  };
  std::vector<GoalLabel> labels;
  std::vector<cv::Rect> wanted;
  const int barWidth = std::max(40, size.width / 16);
  const int barHeight = std::max(4, size.height / 160);
  for (const Goal& goal : sim.level().goals) {
    int index = -1;
    for (int i = 0; i < world.ObjectCount(); ++i)
      if (world.Object(i).name == goal.object) index = i;
    if (index < 0) continue;
    const ObjectState state = world.Object(index);
    const ObjectSpec* spec = sim.level().FindObject(goal.object);
    const Pose2 start = spec ? spec->pose : state.pose;
    const bool met = goal.IsMet(state.pose);
    const cv::Scalar color = met ? c::kGoalMet : c::kGoal;
    double reach = 1.0;  // cm, the object's outline radius
    for (const SliceOutline& slice : world.Slices(index))
      for (int k = 0; k < slice.outline.cols(); ++k)
        reach = std::max(reach, slice.outline.col(k).norm());
    Vec2 labelAt = goal.zone ? RegionCenter(*goal.zone) : state.pose.pos;
    if (goal.angle) {
      const Vec2 dir(std::cos(*goal.angle), std::sin(*goal.angle));
      const Vec2 from = state.pose.pos + (reach + 0.5) * dir;
      const Vec2 to = state.pose.pos + (reach + 3.0) * dir;
      cv::line(img, Fixed(map.ToDisplay(from)), Fixed(map.ToDisplay(to)), color, 3, cv::LINE_AA,
               kShift);
      // the current angle, for comparison
      const Vec2 now(std::cos(state.pose.angle), std::sin(state.pose.angle));
      cv::line(img, Fixed(map.ToDisplay(state.pose.pos + (reach + 0.5) * now)),
               Fixed(map.ToDisplay(state.pose.pos + (reach + 2.0) * now)), c::kContour, 1,
               cv::LINE_AA, kShift);
      if (!goal.zone) labelAt = state.pose.pos + Vec2(0, -(reach + 3.5));
    }
    // goals that share a label name their object, so each bar can be told apart
    std::string text = goal.label.empty() ? goal.object : goal.label;
    const auto sameText = [&](const Goal& other) {
      return &other != &goal && (other.label.empty() ? other.object : other.label) == text;
    };
    const auto& goals = sim.level().goals;
    if (std::any_of(goals.begin(), goals.end(), sameText)) text += " (" + goal.object + ")";
    if (met) text += "  done";
    // the label's box: the text above the anchor, the bar below it
    int baseline = 0;
    const cv::Size ts = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, textScale, 1, &baseline);
    const cv::Point at = Round(map.ToDisplay(labelAt));
    const int width = std::max(ts.width, barWidth);
    wanted.emplace_back(at.x - width / 2, at.y - 4 - ts.height, width, ts.height + 10 + barHeight);
    labels.push_back({text, color, GoalProgress(goal, start, state.pose), ts.height});
  }
  const std::vector<cv::Rect> placed = SpreadLabels(wanted, size);
  for (size_t i = 0; i < labels.size(); ++i) {
    const GoalLabel& label = labels[i];
    const cv::Rect& box = placed[i];
    const int centre = box.x + box.width / 2;
    const cv::Rect bar(centre - barWidth / 2, box.y + label.textHeight + 10, barWidth, barHeight);
    cv::rectangle(img, bar, label.color, 1, cv::LINE_8);
    cv::rectangle(
        img,
        cv::Rect(bar.x, bar.y, static_cast<int>(std::lround(barWidth * label.progress)), barHeight),
        label.color, cv::FILLED, cv::LINE_8);
    int baseline = 0;
    const cv::Size ts =
        cv::getTextSize(label.text, cv::FONT_HERSHEY_SIMPLEX, textScale, 1, &baseline);
    Text(img, label.text, {centre - ts.width / 2, box.y + label.textHeight}, textScale,
         label.color);
  }

  // particles, coloured by their base layer
  const std::vector<ParticleState> particles = world.Particles();
  for (const ParticleState& p : particles) {
    if (options.layer >= 0 &&
        (options.layer < p.baseLayer || options.layer >= p.baseLayer + p.layerCount))
      continue;
    const double radius = std::max(1.5, params.physics.particleRadius * map.PixelsPerCm(p.pos));
    cv::circle(img, Fixed(map.ToDisplay(p.pos)),
               static_cast<int>(std::lround(radius * kShiftScale)), c::Layer(p.baseLayer),
               cv::FILLED, cv::LINE_AA, kShift);
  }

  // contact contours over their particles
  for (const Contact& contact : sim.contacts().contacts) {
    // a hovering hand shows as its shadow, not as an outline
    if (contact.state == ContactState::kLifted || contact.blob.contour.cols() < 2 ||
        contact.blob.hover) {
      continue;
    }
    const std::vector<cv::Point> poly = ToDisplay(contact.blob.contour, Pose2{}, map);
    cv::polylines(img, poly, true, c::kContour, 1, cv::LINE_AA, kShift);
  }

  // successor links: where each reused particle was and where it is driven to
  if (options.successors) {
    for (const PlannedParticle& p : sim.plan().particles) {
      if (p.action != ParticleAction::kReused) continue;
      const auto last = m_lastPositions.find(p.id);
      if (last == m_lastPositions.end()) continue;
      cv::line(img, Fixed(map.ToDisplay(last->second)), Fixed(map.ToDisplay(p.target)),
               cv::Scalar(255, 0, 255), 1, cv::LINE_AA, kShift);
    }
  }
  m_lastPositions.clear();
  for (const ParticleState& p : particles) m_lastPositions[p.id] = p.pos;

  // force vectors at the centre of mass, as long as 60 px per object weight
  if (options.forces) {
    for (int i = 0; i < world.ObjectCount(); ++i) {
      const ObjectState state = world.Object(i);
      const ObjectForces forces = world.Forces(i);
      const bool oneLayer =
          options.layer >= 0 && options.layer < static_cast<int>(forces.layers.size());
      const LayerForces& f =
          oneLayer ? forces.layers[static_cast<size_t>(options.layer)] : forces.total;
      const Vec2 friction = oneLayer ? f.friction : Vec2(f.friction + forces.topFriction);
      const double pxPerDyn = 60.0 / std::max(1e-6, state.mass * params.physics.gravity);
      const auto toDisplayVector = [&](const Vec2& v) {
        Vec2 d(v.x() * pxPerDyn, -v.y() * pxPerDyn);
        if (d.norm() > 200.0) d *= 200.0 / d.norm();
        return d;
      };
      const cv::Point2d com = map.ToDisplay(state.centerOfMass);
      Arrow(img, com, toDisplayVector(f.normal), cv::Scalar(255, 160, 60));
      Arrow(img, com, toDisplayVector(friction), cv::Scalar(40, 140, 255));
    }
  }

  // the heads-up lines; the sensing view's tiles go below them
  std::vector<std::pair<std::string, cv::Scalar>> hud;
  if (options.hud) {
    const FrameStats& s = sim.stats();
    const cv::Scalar white(230, 230, 230);
    std::string first = sim.level().name + "   frame " + std::to_string(sim.Frame()) +
                        Format("   t %.2f s", sim.Time());
    if (overlay.fps > 0) first += Format("   %.1f fps", overlay.fps);
    if (options.layer >= 0) first += "   layer " + std::to_string(options.layer);
    hud.emplace_back(first, white);
    hud.emplace_back(Format("ms  sense %.2f  track %.2f  proxies %.2f  physics %.2f  total %.2f",
                            s.senseMs, s.trackMs, s.proxyMs, s.physicsMs, s.totalMs),
                     white);
    hud.emplace_back("contacts " + std::to_string(s.contacts) + "   particles " +
                         std::to_string(s.particles) + "   bodies " + std::to_string(s.bodies),
                     white);
    if (!overlay.status.empty()) hud.emplace_back(overlay.status, cv::Scalar(120, 230, 255));
  }
  m_size = size;
  m_tableRect = cv::Rect(0, 0, size.width, size.height);
  if (options.sensing) {
    const int top = hud.empty() ? 0 : 6 + TextBoxSize(hud, textScale).height + 4;
    if (SensingView(sim, img, top, m_tableRect, m_sensing)) cv::swap(img, m_sensing);
  }
  int y = 6;
  if (!hud.empty()) y = TextBox(img, hud, {6, 6}, textScale) + 4;
  if (!overlay.error.empty()) {
    std::vector<std::pair<std::string, cv::Scalar>> lines;
    const size_t width = static_cast<size_t>(std::max(30, size.width / 9));
    for (const std::string& line : Wrap(overlay.error, width)) lines.emplace_back(line, c::kError);
    TextBox(img, lines, {6, y}, textScale);
  }
  if (options.help && !overlay.help.empty()) {
    std::vector<std::pair<std::string, cv::Scalar>> lines;
    for (const std::string& line : overlay.help)
      lines.emplace_back(line, cv::Scalar(230, 230, 230));
    TextBox(img, lines, {size.width / 4, size.height / 4}, textScale * 1.2);
  }
}

}  // namespace pg
