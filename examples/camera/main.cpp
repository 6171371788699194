// embed_camera: a program of its own that drives the proxygrasp pipeline from a camera under the
// table (or a video of one) through the library's FrameInput, and prints the objects' poses.
//   embed_camera SOURCE [LEVEL] [--frames N]
// SOURCE: camera:N, /dev/videoN, video:FILE or a video file (a recording made by
// `proxygrasp run LEVEL --record FILE.mkv` replays the level's script). LEVEL: a file, or a name
// in the installed levels (default demo_sort). A source that does not open is an error naming it.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <proxygrasp/level/find.h>
#include <proxygrasp/level/level.h>
#include <proxygrasp/run/frame_input.h>
#include <proxygrasp/run/simulation.h>
#include <string>
#include <vector>

namespace {

void PrintPoses(const pg::Simulation& sim) {
  const pg::LayeredWorld& world = sim.world();
  for (pg::ObjectId i = 0; i < world.ObjectCount(); ++i) {
    const pg::ObjectState o = world.Object(i);
    std::printf("  t=%.2f s  %-10s x=%7.2f cm  y=%7.2f cm  angle=%7.2f deg  contacts=%zu\n",
                sim.Time(), o.name.c_str(), o.pose.pos.x(), o.pose.pos.y(),
                o.pose.angle * 180.0 / M_PI, sim.contacts().contacts.size());
  }
}

bool IsCamera(const std::string& spec) {
  return spec.rfind("camera:", 0) == 0 || spec.rfind("/dev/video", 0) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string source;
  std::string levelArg = "demo_sort";
  long frames = 0;  // 0: until the source ends (a camera: until interrupted)
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) {
      char* end = nullptr;
      frames = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || frames <= 0) {
        std::fprintf(stderr, "embed_camera: --frames takes a positive count (got %s)\n", argv[i]);
        return 2;
      }
    } else if (a.rfind("-", 0) == 0) {
      std::fprintf(stderr, "embed_camera: unknown option %s\n", a.c_str());
      return 2;
    } else {
      positional.push_back(a);
    }
  }
  if (positional.empty() || positional.size() > 2) {
    std::fprintf(stderr,
                 "usage: embed_camera SOURCE [LEVEL] [--frames N]\n"
                 "  SOURCE: camera:N, /dev/videoN, video:FILE or a video file\n");
    return 2;
  }
  source = positional[0];
  if (positional.size() == 2) levelArg = positional[1];

  const std::vector<std::string> dirs = {PROXYGRASP_LEVELS_DIR};
  const pg::Result<std::string> path = pg::FindLevelFile(levelArg, dirs);
  if (!path) {
    std::fprintf(stderr, "embed_camera: %s\n", path.error().Format().c_str());
    return 2;
  }
  const pg::Result<pg::Level> level = pg::LoadLevel(path.value());
  if (!level) {
    std::fprintf(stderr, "%s\n", level.error().Format().c_str());
    return 2;
  }

  // the source; a camera that is not there is an error here, not a silent empty run
  pg::Result<pg::FrameInput> input = pg::FrameInput::Open(source);
  if (!input) {
    std::fprintf(stderr, "embed_camera: cannot open %s: %s\n", source.c_str(),
                 input.error().Format().c_str());
    return 1;
  }
  pg::FrameInput& frames_in = input.value();
  if (frames_in.Peek() != pg::FrameStatus::kOk) {
    std::fprintf(stderr, "embed_camera: %s gives no frame: %s\n", source.c_str(),
                 frames_in.LastError().c_str());
    return 1;
  }

  // the sensor takes the source's image size; a live camera's clear table is estimated from its
  // own frames, a recording of the synthetic table keeps the synthetic camera's background
  pg::LevelParams params = level.value().params;
  params.camera.width = frames_in.PeekedSize().width;
  params.camera.height = frames_in.PeekedSize().height;
  pg::SimulationOptions options;
  options.cameraBackground = !IsCamera(source);
  pg::Simulation sim;
  if (pg::MaybeError e = sim.Start(level.value(), params, options)) {
    std::fprintf(stderr, "embed_camera: %s\n", e->Format().c_str());
    return 2;
  }
  std::printf("%s through %s\n", path.value().c_str(), frames_in.Describe().c_str());

  for (long f = 0; frames == 0 || f < frames; ++f) {
    const pg::Result<pg::FrameStatus> stepped = frames_in.Step(sim);
    if (!stepped) {
      std::fprintf(stderr, "embed_camera: frame %ld: %s\n", f, stepped.error().Format().c_str());
      return 1;
    }
    if (stepped.value() == pg::FrameStatus::kEnd) break;
    if (stepped.value() != pg::FrameStatus::kOk) {
      std::fprintf(stderr, "embed_camera: %s\n", frames_in.LastError().c_str());
      return 1;
    }
    if (f % 30 == 29) PrintPoses(sim);
  }

  for (pg::ObjectId i = 0; i < sim.world().ObjectCount(); ++i) {
    const pg::ObjectState end = sim.world().Object(i);
    const pg::Vec2 begin = level.value().objects[static_cast<size_t>(i)].pose.pos;
    std::printf("moved %s %.2f cm after %lld frames\n", end.name.c_str(),
                (end.pose.pos - begin).norm(), static_cast<long long>(sim.Frame()));
  }
  return 0;
}
