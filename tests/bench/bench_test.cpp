#include "proxygrasp/bench/bench.h"

#include "proxygrasp/sensing/synthetic_camera.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <string>

namespace pg {
namespace {

using ::testing::HasSubstr;

// A small JSON reader for the report: checks the syntax and collects every number under its key
// path ("scenes.0.stages.sense.p50_ms") and every string likewise.
class JsonReader {
 public:
  explicit JsonReader(const std::string& text) : m_text(text) {}

  // true when the whole text is one JSON value
  bool Parse() {
    if (!Value("")) return false;
    Skip();
    return m_pos == m_text.size();
  }

  std::map<std::string, double> numbers;
  std::map<std::string, std::string> strings;
  std::set<std::string> keys;  // every path that holds a value

 private:
  void Skip() {
    while (m_pos < m_text.size() && std::isspace(static_cast<unsigned char>(m_text[m_pos])))
      ++m_pos;
  }
  bool Eat(char c) {
    Skip();
    if (m_pos < m_text.size() && m_text[m_pos] == c) {
      ++m_pos;
      return true;
    }
    return false;
  }
  bool String(std::string& out) {
    if (!Eat('"')) return false;
    out.clear();
    while (m_pos < m_text.size() && m_text[m_pos] != '"') {
      if (m_text[m_pos] == '\\') ++m_pos;
      if (m_pos < m_text.size()) out += m_text[m_pos++];
    }
    return Eat('"');
  }
  bool Value(const std::string& path) {
    keys.insert(path);
    Skip();
    if (m_pos >= m_text.size()) return false;
    const char c = m_text[m_pos];
    if (c == '{') {
      ++m_pos;
      if (Eat('}')) return true;
      do {
        std::string key;
        if (!String(key) || !Eat(':') || !Value(path.empty() ? key : path + "." + key))
          return false;
      } while (Eat(','));
      return Eat('}');
    }
    if (c == '[') {
      ++m_pos;
      if (Eat(']')) return true;
      int index = 0;
      do {
        if (!Value(path + "." + std::to_string(index++))) return false;
      } while (Eat(','));
      return Eat(']');
    }
    if (c == '"') return String(strings[path]);
    if (m_text.compare(m_pos, 4, "null") == 0) {
      m_pos += 4;
      numbers[path] = NAN;  // the report writes a number that is not finite as null
      return true;
    }
    const char* start = m_text.c_str() + m_pos;
    char* end = nullptr;
    const double v = std::strtod(start, &end);
    if (end == start) return false;
    m_pos += static_cast<size_t>(end - start);
    numbers[path] = v;
    return true;
  }

  const std::string& m_text;
  size_t m_pos = 0;
};

// the checks every report's JSON must pass
void ExpectWellFormed(const BenchReport& report) {
  const std::string json = BenchJson(report);
  JsonReader reader(json);
  ASSERT_TRUE(reader.Parse()) << json;
  for (const char* key : {"machine.cpu", "machine.cores", "machine.compiler", "machine.build_type",
                          "scenes", "render", "baselines"}) {
    EXPECT_TRUE(reader.keys.count(key)) << key << " missing in\n" << json;
  }
  for (const auto& [path, v] : reader.numbers) {
    EXPECT_TRUE(std::isfinite(v)) << path;
    // the load average is -1 where /proc/loadavg cannot be read
    if (path.find("load_") == std::string::npos) {
      EXPECT_GE(v, 0.0) << path;
    }
  }
  for (size_t i = 0; i < report.scenes.size(); ++i) {
    const std::string s = "scenes." + std::to_string(i);
    EXPECT_EQ(reader.strings[s + ".name"], report.scenes[i].name);
    EXPECT_TRUE(reader.numbers.count(s + ".p50_ms")) << s;
    EXPECT_TRUE(reader.numbers.count(s + ".p99_ms")) << s;
    for (const char* stage : {"sense", "track", "proxies", "physics", "total"}) {
      EXPECT_TRUE(reader.numbers.count(s + ".stages." + stage + ".p50_ms")) << s << " " << stage;
      EXPECT_TRUE(reader.numbers.count(s + ".stages." + stage + ".p99_ms")) << s << " " << stage;
    }
  }
  for (size_t i = 0; i < report.baselines.size(); ++i) {
    const std::string b = "baselines." + std::to_string(i);
    for (const char* key : {".name", ".ours_ms", ".bare_ms", ".ratio"}) {
      EXPECT_TRUE(reader.keys.count(b + key)) << b << key;
    }
  }
  EXPECT_EQ(reader.keys.count("render." + std::to_string(report.render.size() - 1) + ".p50_ms"),
            1u);
}

TEST(Bench, PercentileIsTheNearestRank) {
  // nearest rank: the ceil(p n)-th smallest of n values, whatever their order
  const std::vector<double> values = {5.0, 1.0, 4.0, 2.0, 3.0};
  EXPECT_EQ(Percentile(values, 0.5), 3.0);   // ceil(2.5) = 3rd
  EXPECT_EQ(Percentile(values, 0.99), 5.0);  // ceil(4.95) = 5th
  EXPECT_EQ(Percentile(values, 0.2), 1.0);   // ceil(1.0) = 1st
  EXPECT_EQ(Percentile(values, 0.01), 1.0);  // ceil(0.05) = 1st
  EXPECT_EQ(Percentile({}, 0.5), 0.0);
}

TEST(Bench, SmallRunGivesEveryFigureAndBaseline) {
  BenchOptions options;
  options.frames = 5;
  options.scenes = {"fingertips10_s3", "flat_hands2_s3_k8"};
  const Result<BenchReport> r = RunBench(options);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const BenchReport& report = r.value();
  ASSERT_EQ(report.scenes.size(), 2u);
  EXPECT_EQ(report.scenes[0].name, "fingertips10_s3");
  EXPECT_EQ(report.scenes[1].name, "flat_hands2_s3_k8");
  EXPECT_EQ(report.render.size(), 2u);
  for (const BenchScene& s : report.scenes) {
    EXPECT_EQ(s.frames, 5) << s.name;
    ASSERT_EQ(s.stages.size(), 5u);
    EXPECT_EQ(s.stages.back().name, "total");
    // every contact of the scene is sensed: 10 fingertips, 2 hands
    EXPECT_DOUBLE_EQ(s.contacts, s.name == "fingertips10_s3" ? 10.0 : 2.0) << s.name;
    EXPECT_GT(s.particles, 0.0) << s.name;
    for (const BenchFigure& f : s.stages) EXPECT_LE(f.p50, f.p99) << s.name << " " << f.name;
  }
  // three baselines per scene, each ours / bare
  ASSERT_EQ(report.baselines.size(), 6u);
  std::set<std::string> names;
  for (const BenchBaseline& b : report.baselines) {
    names.insert(b.name);
    EXPECT_GT(b.bareMs, 0.0) << b.name << " " << b.scene;
    EXPECT_DOUBLE_EQ(b.ratio, b.oursMs / b.bareMs) << b.name << " " << b.scene;
  }
  EXPECT_EQ(names, (std::set<std::string>{"sensing_vs_bare_opencv", "physics_vs_box2d",
                                          "matching_vs_exhaustive"}));
  ExpectWellFormed(report);
}

TEST(Bench, AllScenesRunByDefault) {
  BenchOptions options;
  options.frames = 2;
  const Result<BenchReport> r = RunBench(options);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  std::vector<std::string> names;
  for (const BenchScene& s : r.value().scenes) names.push_back(s.name);
  EXPECT_EQ(names, (std::vector<std::string>{"fingertips10_s3", "flat_hands2_s3_k8",
                                             "five_hands4_s3", "flat_hands8"}));
  EXPECT_EQ(names, BenchSceneNames());
  // the eight hands are eight contacts
  EXPECT_DOUBLE_EQ(r.value().scenes.back().contacts, 8.0);
  ExpectWellFormed(r.value());
}

TEST(Bench, RepeatsPoolTheirFrames) {
  BenchOptions options;
  options.frames = 2;
  options.repeat = 2;
  options.scenes = {"flat_hands8"};
  const Result<BenchReport> r = RunBench(options);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value().scenes.at(0).frames, 4);
  EXPECT_EQ(r.value().repeat, 2);
}

TEST(Bench, PhysicsThreadsLeaveTheStateBitIdenticalAndTheHashSeesAChange) {
  // issue 17: physics.threads = 2 against 1 on the four-hand scene gives the same state to the bit
  BenchOptions options;
  options.frames = 30;
  options.scenes = {"five_hands4_s3"};
  options.clock = TimerClock::kWall;
  options.sets = {"physics.threads=1"};
  const Result<BenchReport> one = RunBench(options);
  ASSERT_TRUE(one.ok()) << one.error().Format();
  options.sets = {"physics.threads=2"};
  const Result<BenchReport> two = RunBench(options);
  ASSERT_TRUE(two.ok()) << two.error().Format();
  EXPECT_EQ(one.value().scenes.at(0).stateHash, two.value().scenes.at(0).stateHash);
  EXPECT_THAT(BenchJson(two.value()), HasSubstr("\"sets\": [\"physics.threads=2\"]"));
  EXPECT_THAT(BenchJson(two.value()), HasSubstr("\"clock\": \"wall\""));
  // a change that moves the objects changes the hash: it is not blind
  options.sets = {"physics.substeps=3"};
  const Result<BenchReport> other = RunBench(options);
  ASSERT_TRUE(other.ok()) << other.error().Format();
  EXPECT_NE(one.value().scenes.at(0).stateHash, other.value().scenes.at(0).stateHash);
}

TEST(Bench, BadOptionsAreNamed) {
  BenchOptions options;
  options.frames = 0;
  Result<BenchReport> r = RunBench(options);
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.error().Format(), HasSubstr("--frames must be >= 1 (got 0)"));

  options.frames = 1;
  options.repeat = -1;
  r = RunBench(options);
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.error().Format(), HasSubstr("--repeat must be >= 1 (got -1)"));

  options.repeat = 1;
  options.scenes = {"fingertips10_s3", "hands9"};
  r = RunBench(options);
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.error().Format(), HasSubstr("unknown scene 'hands9'"));
  EXPECT_THAT(r.error().Format(), HasSubstr("flat_hands8"));

  options.scenes = {"flat_hands8"};
  options.sets = {"physics.nothing=1"};
  r = RunBench(options);
  ASSERT_FALSE(r.ok());
  EXPECT_THAT(r.error().Format(), HasSubstr("--set physics.nothing=1"));
}

TEST(BareSensingChain, FindsEachFingertip) {
  const TableParams table;
  SyntheticCamera camera(SyntheticCameraParams{}, table);
  std::vector<ContactShape> shapes;
  ASSERT_TRUE(DemoScene("fingers", 20, table, shapes));
  const cv::Mat frame = camera.Render(shapes);
  // the default chain (high-pass on) and one without the high-pass both see ten blobs
  BareSensingChain chain(SensingParams{}, table, camera.Background());
  EXPECT_EQ(chain.Step(frame), 10u);
  SensingParams plain;
  plain.highpassWidth = 0.0;
  plain.threshold = 60.0;
  BareSensingChain bare(plain, table, camera.Background());
  EXPECT_EQ(bare.Step(frame), 10u);
  // a clear table has none
  EXPECT_EQ(chain.Step(camera.Render({})), 0u);
}

}  // namespace
}  // namespace pg
