// embed_contours: a program of its own that drives the proxygrasp pipeline with contours it makes
// itself, as a table app with its own tracker would. No camera: a fingertip's outline (a circle
// of 0.8 cm) slides across the table into the level's first object, frame by frame, and the
// objects' poses are read back from the physics.
//   embed_contours [LEVEL] [--frames N]     LEVEL: a file, or a name in the installed levels
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <proxygrasp/level/find.h>
#include <proxygrasp/level/level.h>
#include <proxygrasp/run/simulation.h>
#include <string>
#include <vector>

namespace {

// a fingertip's outline: a CCW circle of `radius` cm around `centre`, one point every ~0.3 cm
pg::Blob Fingertip(const pg::Vec2& centre, double radius) {
  constexpr int kPoints = 16;
  pg::Blob blob;
  blob.contour.resize(2, kPoints);
  for (int i = 0; i < kPoints; ++i) {
    const double a = 2.0 * M_PI * i / kPoints;
    blob.contour.col(i) = centre + radius * pg::Vec2(std::cos(a), std::sin(a));
  }
  blob.centroid = centre;
  blob.area = M_PI * radius * radius;
  blob.boundsMin = centre - pg::Vec2(radius, radius);
  blob.boundsMax = centre + pg::Vec2(radius, radius);
  return blob;
}

void PrintPoses(const pg::Simulation& sim) {
  const pg::LayeredWorld& world = sim.world();
  for (pg::ObjectId i = 0; i < world.ObjectCount(); ++i) {
    const pg::ObjectState o = world.Object(i);
    std::printf("  t=%.2f s  %-10s x=%7.2f cm  y=%7.2f cm  angle=%7.2f deg%s\n", sim.Time(),
                o.name.c_str(), o.pose.pos.x(), o.pose.pos.y(), o.pose.angle * 180.0 / M_PI,
                o.held ? "  held" : "");
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string levelArg = "side_push";
  long frames = 120;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) {
      char* end = nullptr;
      frames = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || frames <= 0) {
        std::fprintf(stderr, "embed_contours: --frames takes a positive count (got %s)\n", argv[i]);
        return 2;
      }
    } else if (a.rfind("-", 0) == 0) {
      std::fprintf(stderr, "embed_contours: unknown option %s\n", a.c_str());
      return 2;
    } else {
      levelArg = a;
    }
  }

  // the level: a file, or a name among the installed levels
  const std::vector<std::string> dirs = {PROXYGRASP_LEVELS_DIR};
  const pg::Result<std::string> path = pg::FindLevelFile(levelArg, dirs);
  if (!path) {
    std::fprintf(stderr, "embed_contours: %s\n", path.error().Format().c_str());
    return 2;
  }
  const pg::Result<pg::Level> level = pg::LoadLevel(path.value());
  if (!level) {
    std::fprintf(stderr, "%s\n", level.error().Format().c_str());
    return 2;
  }
  if (level.value().objects.empty()) {
    std::fprintf(stderr, "embed_contours: %s has no objects to push\n", path.value().c_str());
    return 2;
  }

  // the pipeline, with the level's own parameters
  pg::Simulation sim;
  if (pg::MaybeError e = sim.Start(level.value(), level.value().params)) {
    std::fprintf(stderr, "embed_contours: %s\n", e->Format().c_str());
    return 2;
  }

  // the finger starts 10 cm left of the first object and slides right, past its centre by 2 cm,
  // in the first 3/4 of the run; then it stays
  const pg::ObjectState start = sim.world().Object(0);
  const pg::Vec2 from = start.pose.pos - pg::Vec2(10.0, 0.0);
  const pg::Vec2 to = start.pose.pos + pg::Vec2(2.0, 0.0);
  const long slideFrames = frames * 3 / 4;
  std::printf("%s: a fingertip slides from (%.1f, %.1f) to (%.1f, %.1f) cm over %ld frames\n",
              path.value().c_str(), from.x(), from.y(), to.x(), to.y(), slideFrames);
  for (long f = 0; f < frames; ++f) {
    const double s = std::min(1.0, static_cast<double>(f) / static_cast<double>(slideFrames));
    pg::ContourFrame contours;
    contours.index = sim.Frame();
    contours.time = sim.Time();
    contours.blobs.push_back(Fingertip(from + s * (to - from), 0.8));
    if (pg::MaybeError e = sim.StepContours(contours)) {
      std::fprintf(stderr, "embed_contours: frame %ld: %s\n", f, e->Format().c_str());
      return 1;
    }
    if (f % 30 == 29) PrintPoses(sim);
  }

  // how far each object went
  for (pg::ObjectId i = 0; i < sim.world().ObjectCount(); ++i) {
    const pg::ObjectState end = sim.world().Object(i);
    const pg::Vec2 begin = level.value().objects[static_cast<size_t>(i)].pose.pos;
    std::printf("moved %s %.2f cm\n", end.name.c_str(), (end.pose.pos - begin).norm());
  }
  return 0;
}
