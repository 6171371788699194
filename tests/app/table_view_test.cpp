// The table view draws into a cv::Mat without any window: objects, particles, contours and goals
// land where the level puts them, and the overlays appear when asked.
#include "proxygrasp/app/table_view.h"

#include "pixels.h"
#include "test_paths.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/level/script.h"
#include "proxygrasp/sensing/calibration.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace pg {
namespace {

using test::FindColor;

// per-channel colour tolerance: antialiased edges blend, interiors are exact
constexpr int kColorTolerance = 12;

const std::string kLevel = std::string(pg::test::TestDataDir()) + "/box_goal.toml";

Level LoadTestLevel() {
  Result<Level> level = LoadLevel(kLevel);
  EXPECT_TRUE(level.ok()) << (level.ok() ? "" : level.error().Format());
  return level.ok() ? level.value() : Level{};
}

TEST(DisplayMap, FitsTheTableCentredWithYUp) {
  TableParams table;  // 61 x 46 cm
  const DisplayMap map = DisplayMap::Fit(table, {1024, 768}, 8);
  // the height limits: (768 - 16) / 46 px per cm; the width is centred
  const double scale = 752.0 / 46.0;
  const double left = 0.5 * (1024 - scale * 61.0);
  const cv::Point2d origin = map.ToDisplay({0, 0});
  const cv::Point2d far = map.ToDisplay({61, 46});
  EXPECT_NEAR(origin.x, left, 1e-9);
  EXPECT_NEAR(origin.y, 8 + 752, 1e-9);
  EXPECT_NEAR(far.x, left + scale * 61.0, 1e-9);
  EXPECT_NEAR(far.y, 8, 1e-9);
  EXPECT_NEAR(map.PixelsPerCm({30, 20}), scale, 1e-9);
  // the inverse maps back (round-off only)
  const Vec2 back = map.ToTable(map.ToDisplay({12.5, 33.25}));
  EXPECT_NEAR(back.x(), 12.5, 1e-9);
  EXPECT_NEAR(back.y(), 33.25, 1e-9);
}

TEST(DisplayMap, UsesTheCalibrationFileWhenTheLevelNamesOne) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("pg_view_calib_" + std::to_string(getpid()) + ".yaml"))
                               .string();
  Calibration calibration = LinearCalibration({640, 480}, TableParams{});
  calibration.tableToDisplay = cv::Matx33d(10, 0, 50, 0, -10, 600, 0, 0, 1);
  ASSERT_FALSE(SaveCalibration(path, calibration));
  LevelParams params;
  params.sensing.calibration = path;
  Result<DisplayMap> map = LevelDisplayMap(params, {1024, 768});
  ASSERT_TRUE(map.ok()) << map.error().Format();
  const cv::Point2d p = map.value().ToDisplay({3, 4});
  EXPECT_NEAR(p.x, 80, 1e-9);
  EXPECT_NEAR(p.y, 560, 1e-9);
  std::filesystem::remove(path);

  params.sensing.calibration = path;  // now missing
  Result<DisplayMap> missing = LevelDisplayMap(params, {1024, 768});
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().Format().find(path), std::string::npos) << missing.error().Format();
}

TEST(GoalProgress, IsTheFractionOfDistanceAndAngleCovered) {
  Goal zone;
  zone.object = "box";
  Region circle;
  circle.kind = Region::Kind::kCircle;
  circle.center = Vec2(10, 0);
  circle.radius = 2.0;
  zone.zone = circle;
  // start 8 cm from the zone's edge, now 4: half way
  EXPECT_NEAR(GoalProgress(zone, {{0, 0}, 0}, {{4, 0}, 0}), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(GoalProgress(zone, {{0, 0}, 0}, {{9, 0}, 0}), 1.0);
  EXPECT_DOUBLE_EQ(GoalProgress(zone, {{0, 0}, 0}, {{-3, 0}, 0}), 0.0);

  Goal turn;
  turn.object = "dial";
  turn.angle = DegToRad(90);
  turn.tolerance = DegToRad(10);
  // 90 deg off at the start, 50 now: (50 - 10) of (90 - 10) left, half way
  EXPECT_NEAR(GoalProgress(turn, {{0, 0}, 0}, {{0, 0}, DegToRad(40)}), 0.5, 1e-12);
  // a full turn further is the same angle
  EXPECT_DOUBLE_EQ(GoalProgress(turn, {{0, 0}, 0}, {{0, 0}, DegToRad(90 + 360)}), 1.0);

  // both: the smaller
  Goal both = zone;
  both.angle = turn.angle;
  both.tolerance = turn.tolerance;
  EXPECT_NEAR(GoalProgress(both, {{0, 0}, 0}, {{9, 0}, DegToRad(40)}), 0.5, 1e-12);
}

TEST(ViewOptions, ParsesAListOfOverlays) {
  ViewOptions options;
  ASSERT_FALSE(ParseViewOptions("forces,successors,camera,layer=2,nohud", options));
  EXPECT_TRUE(options.forces);
  EXPECT_TRUE(options.successors);
  EXPECT_TRUE(options.cameraImage);
  EXPECT_FALSE(options.hud);
  EXPECT_EQ(options.layer, 2);
  EXPECT_FALSE(options.sensing);
  ASSERT_FALSE(ParseViewOptions("sensing", options));
  EXPECT_TRUE(options.sensing);
  ASSERT_FALSE(ParseViewOptions("", options));
  const MaybeError bad = ParseViewOptions("forces,frcs", options);
  ASSERT_TRUE(bad);
  EXPECT_NE(bad->message.find("unknown view 'frcs'"), std::string::npos) << bad->message;
  EXPECT_TRUE(ParseViewOptions("layer=x", options));
}

bool AnyOverlap(const std::vector<cv::Rect>& boxes) {
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j)
      if ((boxes[i] & boxes[j]).area() > 0) return true;
  return false;
}

TEST(SpreadLabels, MovesOverlappingLabelsApartAndKeepsFreeOnes) {
  const cv::Size image(800, 600);
  // three labels wanting one place, one overlapping them partly, one far away
  const std::vector<cv::Rect> wanted = {{100, 100, 120, 30},
                                        {100, 100, 120, 30},
                                        {100, 100, 120, 30},
                                        {150, 110, 80, 20},
                                        {500, 400, 100, 30}};
  const std::vector<cv::Rect> placed = SpreadLabels(wanted, image);
  ASSERT_EQ(placed.size(), wanted.size());
  EXPECT_FALSE(AnyOverlap(placed));
  // the first and the free one keep their places; the others move straight up or down, the
  // nearest free place first (below before above)
  EXPECT_EQ(placed[0], wanted[0]);
  EXPECT_EQ(placed[4], wanted[4]);
  EXPECT_EQ(placed[1], wanted[1] + cv::Point(0, 30 + kLabelGap));
  EXPECT_EQ(placed[2], wanted[2] - cv::Point(0, 30 + kLabelGap));
  for (size_t i = 0; i < placed.size(); ++i) EXPECT_EQ(placed[i].x, wanted[i].x) << i;
}

TEST(SpreadLabels, StaysInsideTheImage) {
  const cv::Size image(400, 300);
  // at the bottom edge the second label goes above; one half outside comes in
  const std::vector<cv::Rect> wanted = {{10, 270, 100, 30}, {10, 270, 100, 30}, {200, 290, 50, 20}};
  const std::vector<cv::Rect> placed = SpreadLabels(wanted, image);
  EXPECT_FALSE(AnyOverlap(placed));
  EXPECT_EQ(placed[1].y, 270 - 30 - kLabelGap);
  EXPECT_EQ(placed[2].y, 290 - 20 - kLabelGap);
  for (const cv::Rect& r : placed) EXPECT_EQ(r & cv::Rect({0, 0}, image), r);
}

TEST(SpreadLabels, LabelsThatCannotAllFitKeepTheirPlace) {
  // a picture with room for two 40 px labels only
  const std::vector<cv::Rect> wanted(3, cv::Rect(0, 0, 50, 40));
  const std::vector<cv::Rect> placed = SpreadLabels(wanted, {60, 90});
  EXPECT_EQ(placed[0], wanted[0]);
  EXPECT_EQ(placed[1].y, 40 + kLabelGap);
  EXPECT_EQ(placed[2], wanted[2]);
}

class TableViewTest : public ::testing::Test {
 protected:
  void SetUp() override {
    level = LoadTestLevel();
    ASSERT_FALSE(sim.Start(level, level.params));
    for (int i = 0; i < kFrames; ++i) ASSERT_FALSE(sim.StepScript());
    map = DisplayMap::Fit(level.params.table, kSize);
  }

  static constexpr int kFrames = 30;
  const cv::Size kSize{1024, 768};
  Level level;
  Simulation sim;
  DisplayMap map;
};

TEST_F(TableViewTest, DrawsTheBoxWhereTheLevelPutsIt) {
  TableView view;
  const cv::Mat picture = view.Draw(sim, map, kSize, {});
  ASSERT_EQ(picture.size(), kSize);
  ASSERT_EQ(picture.type(), CV_8UC3);

  // the top slice is the object's full colour
  const test::ColorPixels box = FindColor(picture, view_colors::Object(0), kColorTolerance);
  const double ppcm = map.PixelsPerCm({30, 23});
  const double expected = 36.0 * ppcm * ppcm;  // 6 x 6 cm
  // the outline (1 px of a darker shade) and the turn tick take a few percent off the area
  EXPECT_GT(box.count, 0.9 * expected);
  EXPECT_LT(box.count, 1.02 * expected);
  const Vec2 centre = map.ToTable(box.centroid - cv::Point2d(0.5, 0.5));
  // nothing touched the box; 0.1 cm is 1.6 px, more than the tick's pull on the centroid
  EXPECT_NEAR(centre.x(), 30.0, 0.1);
  EXPECT_NEAR(centre.y(), 23.0, 0.1);
}

TEST_F(TableViewTest, DrawsParticlesAroundTheFinger) {
  TableView view;
  const cv::Mat picture = view.Draw(sim, map, kSize, {});
  // the finger's particles sit in layer 0 on its contour, a ring around the scripted position
  const test::ColorPixels particles = FindColor(picture, view_colors::Layer(0), kColorTolerance);
  ASSERT_GT(particles.count, 50);
  const std::vector<ContactShape> shapes = ShapesAt(level.script, sim.Time() - sim.FrameDuration());
  ASSERT_EQ(shapes.size(), 1u);
  const Vec2 finger = shapes[0].pose.pos;
  const Vec2 centre = map.ToTable(particles.centroid - cv::Point2d(0.5, 0.5));
  // an evenly sampled ring's centroid is its centre; sensing noise and one frame of motion
  // (0.08 cm) stay well inside 0.3 cm
  EXPECT_NEAR(centre.x(), finger.x(), 0.3);
  EXPECT_NEAR(centre.y(), finger.y(), 0.3);
  // and they stay within the finger's reach: radius 0.8 cm plus a particle and a pixel
  const cv::Point2d a = map.ToDisplay(finger + Vec2(-1.4, 1.4));
  const cv::Point2d b = map.ToDisplay(finger + Vec2(1.4, -1.4));
  EXPECT_TRUE(cv::Rect(cv::Point(a), cv::Point(b)).contains(particles.bounds.tl()));
  EXPECT_TRUE(cv::Rect(cv::Point(a), cv::Point(b)).contains(particles.bounds.br()));
  // the contour of the contact is drawn too
  EXPECT_GT(FindColor(picture, view_colors::kContour, kColorTolerance).count, 30);
}

TEST_F(TableViewTest, DrawsTheGoalZone) {
  TableView view;
  const cv::Mat picture = view.Draw(sim, map, kSize, {});
  const test::ColorPixels goal = FindColor(picture, view_colors::kGoal, kColorTolerance);
  const cv::Point2d lo = map.ToDisplay({45, 30});
  const cv::Point2d hi = map.ToDisplay({55, 40});
  // a 2 px outline: its bounds are the zone's to within the line width
  EXPECT_NEAR(goal.bounds.x, lo.x, 2.5);
  EXPECT_NEAR(goal.bounds.x + goal.bounds.width, hi.x, 2.5);
  EXPECT_NEAR(goal.bounds.y, hi.y, 2.5);
  EXPECT_NEAR(goal.bounds.y + goal.bounds.height, lo.y, 2.5);
  // four sides of ~10 cm at 2 px
  EXPECT_GT(goal.count, 4 * 10 * map.PixelsPerCm({50, 35}));
  // the box is far from the zone: the goal is not met
  EXPECT_EQ(FindColor(picture, view_colors::kGoalMet, kColorTolerance).count, 0);
}

TEST_F(TableViewTest, GoalsSharingAZoneAndLabelGetSeparateLabels) {
  // the level's goal, and a second goal for the same object, zone and label
  TableView view;
  const cv::Mat one = view.Draw(sim, map, kSize, {});
  Level twoGoals = level;
  twoGoals.goals.push_back(twoGoals.goals[0]);
  Simulation twin;
  ASSERT_FALSE(twin.Start(twoGoals, twoGoals.params));
  for (int i = 0; i < kFrames; ++i) ASSERT_FALSE(twin.StepScript());
  const cv::Mat two = view.Draw(twin, map, kSize, {});

  // the goal colour inside the zone (its 2 px outline left out): text and bars only
  const cv::Point2d lo = map.ToDisplay({45, 30});
  const cv::Point2d hi = map.ToDisplay({55, 40});
  const cv::Rect inside(cv::Point(static_cast<int>(lo.x) + 4, static_cast<int>(hi.y) + 4),
                        cv::Point(static_cast<int>(hi.x) - 4, static_cast<int>(lo.y) - 4));
  const test::ColorPixels single = FindColor(one(inside), view_colors::kGoal, kColorTolerance);
  const test::ColorPixels pair = FindColor(two(inside), view_colors::kGoal, kColorTolerance);
  ASSERT_GT(single.count, 50);
  // two labels one above the other: more than twice as tall as one, and twice the ink or more
  // (each names its object, so each is wider than the one alone)
  EXPECT_GE(pair.bounds.height, 2 * single.bounds.height + kLabelGap - 1)
      << single.bounds << " " << pair.bounds;
  EXPECT_GT(pair.count, 2 * single.count);
}

TEST_F(TableViewTest, TableAndOutsideHaveTheirColours) {
  TableView view;
  const cv::Mat picture = view.Draw(sim, map, kSize, {});
  const cv::Point empty(map.ToDisplay({50, 8}));
  EXPECT_EQ(picture.at<cv::Vec3b>(empty), cv::Vec3b(38, 34, 30));
  EXPECT_EQ(picture.at<cv::Vec3b>(kSize.height / 2, 2), cv::Vec3b(12, 12, 12));
}

TEST_F(TableViewTest, OneLayerHidesTheOthers) {
  TableView view;
  ViewOptions options;
  options.layer = 5;  // the box fills layers 0..2 and the finger's stacks layer 0
  const cv::Mat picture = view.Draw(sim, map, kSize, options);
  EXPECT_EQ(FindColor(picture, view_colors::Object(0), kColorTolerance).count, 0);
  EXPECT_EQ(FindColor(picture, view_colors::Layer(0), kColorTolerance).count, 0);
  options.layer = 0;
  const cv::Mat layer0 = view.Draw(sim, map, kSize, options);
  // the bottom slice is darker than the top; particles of layer 0 are shown
  EXPECT_EQ(FindColor(layer0, view_colors::Object(0), kColorTolerance).count, 0);
  EXPECT_GT(FindColor(layer0, view_colors::Object(0) * (0.35 + 0.65 / 3), kColorTolerance).count,
            1000);
  EXPECT_GT(FindColor(layer0, view_colors::Layer(0), kColorTolerance).count, 50);
}

TEST_F(TableViewTest, SuccessorLinksJoinLastAndNextPositions) {
  TableView view;
  ViewOptions options;
  options.successors = true;
  const cv::Scalar magenta(255, 0, 255);
  // the first picture has no last picture to link to
  EXPECT_EQ(FindColor(view.Draw(sim, map, kSize, options), magenta, 40).count, 0);
  // six frames at 5 cm/s later the finger's particles are 0.5 cm (8 px) from where they were drawn
  for (int i = 0; i < 6; ++i) ASSERT_FALSE(sim.StepScript());
  const test::ColorPixels links = FindColor(view.Draw(sim, map, kSize, options), magenta, 40);
  EXPECT_GT(links.count, 20);
  // they point along the motion (+x): the links are wider than tall
  EXPECT_GT(links.bounds.width, 6);
}

TEST_F(TableViewTest, ShowsErrorsInRed) {
  TableView view;
  Overlay overlay;
  EXPECT_EQ(FindColor(view.Draw(sim, map, kSize, {}, overlay), view_colors::kError, 30).count, 0);
  overlay.error = "levels/box.toml:12:5: friction must be >= 0 (got -0.2)";
  const test::ColorPixels red =
      FindColor(view.Draw(sim, map, kSize, {}, overlay), view_colors::kError, 30);
  EXPECT_GT(red.count, 100);
  // below the heads-up lines, at the left
  EXPECT_LT(red.bounds.x, 40);
  EXPECT_LT(red.bounds.y, kSize.height / 4);
}

TEST_F(TableViewTest, CameraImageShowsUnderTheDrawing) {
  TableView view;
  ViewOptions options;
  const cv::Point empty(map.ToDisplay({50, 8}));
  const cv::Vec3b plain = view.Draw(sim, map, kSize, options).at<cv::Vec3b>(empty);
  options.cameraImage = true;
  const cv::Vec3b withImage = view.Draw(sim, map, kSize, options).at<cv::Vec3b>(empty);
  // the camera's background (about 40 grey) is blended in: the table gets brighter
  EXPECT_GT(withImage[1], plain[1] + 5);
}

// pixels of the preview's labels (yellow text): well more green and red than blue, which no grey
// stage image and no green outline has
int YellowPixels(const cv::Mat& bgr) {
  int n = 0;
  for (int v = 0; v < bgr.rows; ++v)
    for (int u = 0; u < bgr.cols; ++u) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(v, u);
      n += p[1] > p[0] + 60 && p[2] > p[0] + 60;
    }
  return n;
}

// pixels of the contact outlines on the camera image (green): green well above blue and red
int GreenPixels(const cv::Mat& bgr) {
  int n = 0;
  for (int v = 0; v < bgr.rows; ++v)
    for (int u = 0; u < bgr.cols; ++u) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(v, u);
      n += p[1] > p[0] + 60 && p[1] > p[2] + 60;
    }
  return n;
}

TEST_F(TableViewTest, SensingViewShowsTheTableAndEveryStageInAGrid) {
  TableView view;
  ViewOptions options;
  options.sensing = true;
  options.hud = false;  // the heads-up lines would cover part of the first tile
  const cv::Mat picture = view.Draw(sim, map, kSize, options);
  ASSERT_EQ(picture.size(), kSize);
  // 8 tiles of the 640x480 camera image in 1024x768 px: 3 columns of 3 rows show them largest
  // (1024 / 3 = 341 px wide, against 256 px for 4 columns of 2 rows)
  const cv::Size camera = sim.CameraSize();
  ASSERT_EQ(camera, cv::Size(640, 480));
  const cv::Size tile(341, 256);  // 341 px wide at the camera's 4:3, give or take rounding
  const cv::Point origin((kSize.width - 3 * tile.width) / 2, (kSize.height - 3 * tile.height) / 2);
  // a tile's rectangle grown (or shrunk) by `margin` px, which covers the rounding of its size
  const auto slot = [&](int i, int margin) {
    const cv::Rect r(origin.x + (i % 3) * tile.width - margin,
                     origin.y + (i / 3) * tile.height - margin, tile.width + 2 * margin,
                     tile.height + 2 * margin);
    return r & cv::Rect(cv::Point(0, 0), kSize);
  };
  // the table drawing, box and all, in the first tile only
  const test::ColorPixels box = FindColor(picture, view_colors::Object(0), kColorTolerance);
  ASSERT_GT(box.count, 0);
  EXPECT_EQ((box.bounds & slot(0, 3)), box.bounds);
  // the contact's outline on the camera image, in the second tile only
  EXPECT_GT(GreenPixels(picture(slot(1, -3))), 10);
  EXPECT_EQ(GreenPixels(picture), GreenPixels(picture(slot(1, 3))));
  // each stage's tile has its label
  for (int k = 0; k < kSensingStageCount; ++k)
    EXPECT_GT(YellowPixels(picture(slot(k + 1, -3))), 20) << kSensingStageNames[k];
  // and without the option, the table drawing alone: contacts in light grey, no green outline
  EXPECT_EQ(GreenPixels(view.Draw(sim, map, kSize, {})), 0);
}

TEST(SensingTiles, KeepTheTopFreeAndDoNotOverlap) {
  // without a top band, 8 tiles of a 640x480 camera in 1024x768 px: 3 columns of 3 rows
  std::vector<cv::Rect> tiles = SensingTiles({1024, 768}, {640, 480}, 0);
  ASSERT_EQ(tiles.size(), 8u);
  EXPECT_EQ(tiles[0].size(), cv::Size(341, 256));
  for (const cv::Size picture : {cv::Size(1024, 768), cv::Size(1920, 1080), cv::Size(800, 1280)}) {
    for (int top : {0, 40, 90}) {
      tiles = SensingTiles(picture, {640, 480}, top);
      ASSERT_EQ(tiles.size(), 8u);
      for (size_t i = 0; i < tiles.size(); ++i) {
        EXPECT_GE(tiles[i].y, top);
        EXPECT_EQ(tiles[i] & cv::Rect(cv::Point(0, 0), picture), tiles[i]);
        // the camera's 4:3, to the pixel the sizes are rounded to
        EXPECT_NEAR(tiles[i].width * 3.0, tiles[i].height * 4.0, 4.0);
        for (size_t j = 0; j < i; ++j) EXPECT_TRUE((tiles[i] & tiles[j]).empty());
      }
    }
  }
  EXPECT_TRUE(SensingTiles({1024, 768}, {640, 480}, 768).empty());
}

TEST(SensingTiles, TheDepthChainsSixTiles) {
  // the table and the depth chain's 5 stages in 1280x960 px: 2 columns of 3 rows would give tiles
  // of min(1280 / 1280, 960 / 1440) = 0.667 of the camera's size, 3 columns of 2 rows
  // min(1280 / 1920, 960 / 960) = 0.667 too (the first found is kept: 2 columns), 4 columns 0.5:
  // at 0.667, tiles of 426x320
  const std::vector<cv::Rect> tiles =
      SensingTiles({1280, 960}, {640, 480}, 0, kDepthStageCount + 1);
  ASSERT_EQ(tiles.size(), 6u);
  for (const cv::Rect& t : tiles) EXPECT_EQ(t.size(), cv::Size(426, 320));
  EXPECT_TRUE(SensingTiles({1280, 960}, {640, 480}, 0, 0).empty());
}

TEST_F(TableViewTest, SensingViewKeepsItsTilesBelowTheHeadsUpLinesAndMapsTheMouseThroughItsTable) {
  TableView view;
  ViewOptions options;
  options.sensing = true;  // the heads-up lines are on by default
  const cv::Mat picture = view.Draw(sim, map, kSize, options);
  const cv::Rect table = view.tableRect();
  ASSERT_LT(table.width, kSize.width);
  // The heads-up box darkens what is under it (x 0.35): outside every tile that is the outside
  // colour (12) made 4. Every row of the box has such pixels left of the grid, and all lie above
  // the tiles.
  int boxBottom = -1;
  for (int y = 0; y < picture.rows; ++y)
    for (int x = 0; x < 6 + 40; ++x)
      if (picture.at<cv::Vec3b>(y, x) == cv::Vec3b(4, 4, 4)) boxBottom = y;
  ASSERT_GT(boxBottom, 20);
  EXPECT_LT(boxBottom, table.y);
  // the picture's table tile maps onto the full drawing: its corner to the drawing's corner, and
  // the box found there to where the level puts it (30, 23) cm; one picture pixel is
  // 1024 / table.width drawing pixels, 0.3 cm covers it and the outline's pull
  EXPECT_EQ(view.PictureToDisplay(cv::Point2d(table.x, table.y)), cv::Point2d(0, 0));
  const test::ColorPixels box = FindColor(picture(table), view_colors::Object(0), kColorTolerance);
  ASSERT_GT(box.count, 0);
  const Vec2 centre = map.ToTable(
      view.PictureToDisplay(cv::Point2d(table.x + box.centroid.x, table.y + box.centroid.y)));
  EXPECT_NEAR(centre.x(), 30.0, 0.3);
  EXPECT_NEAR(centre.y(), 23.0, 0.3);
  // without the sensing view a picture point is the drawing's point
  view.Draw(sim, map, kSize, {});
  EXPECT_EQ(view.PictureToDisplay(cv::Point2d(100.5, 200.5)), cv::Point2d(100.5, 200.5));
}

}  // namespace
}  // namespace pg
