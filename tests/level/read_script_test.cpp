#include "proxygrasp/core/units.h"
#include "proxygrasp/level/level.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "level/level_test_util.h"

namespace pg {
namespace {

using test::ErrorOf;

TEST(LevelErrors, UnknownScriptContactAndKeyframeKeys) {
  EXPECT_EQ(ErrorOf("[script]\nduraton = 3\n"),
            "inline.toml:2:1: unknown key 'duraton' in [script] (did you mean 'duration'?)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nradus = 1\n"
                    "keys = [{t = 0, pos = [1, 1]}]\n"),
            "inline.toml:4:1: unknown key 'radus' in a contact (did you mean 'radius'?)");
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 0, pos = [1, 1], angel = 3}]\n"),
            "inline.toml:4:31: unknown key 'angel' in a keyframe (did you mean 'angle'?)");
}

TEST(LevelScript, KeyframesReadAHeightThatDefaultsToTouching) {
  const Result<Level> level = ParseLevel(
      "[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
      "keys = [{t = 0, pos = [1, 1]}, {t = 1, pos = [2, 1], height = 2.5}]\n",
      "inline.toml");
  ASSERT_TRUE(level.ok()) << level.error().Format();
  const std::vector<Keyframe>& keys = level.value().script.contacts.at(0).keys;
  EXPECT_EQ(keys.at(0).height, 0.0);
  EXPECT_EQ(keys.at(1).height, 2.5);
  // below the table is not a height
  EXPECT_THAT(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                      "keys = [{t = 0, pos = [1, 1], height = -1}]\n"),
              testing::HasSubstr("height"));
}

TEST(LevelErrors, KeyframeOutOfOrder) {
  EXPECT_EQ(
      ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\nkeys = [\n"
              "  {t = 0, pos = [1, 1]},\n  {t = 1, pos = [2, 1]},\n  {t = 0.5, pos = [3, 1]},\n"
              "]\n"),
      "inline.toml:7:3: keyframe out of order: t = 0.5 s is not after the previous "
      "keyframe's t = 1 s");
  // equal times are out of order too: a contact cannot be in two places at once
  EXPECT_EQ(ErrorOf("[[script.contacts]]\nname = \"f\"\nshape = \"circle\"\n"
                    "keys = [{t = 1, pos = [1, 1]}, {t = 1, pos = [2, 1]}]\n"),
            "inline.toml:4:32: keyframe out of order: t = 1 s is not after the previous "
            "keyframe's t = 1 s");
}

TEST(LevelErrors, DurationBeforeTheLastKeyframe) {
  EXPECT_EQ(ErrorOf("[script]\nduration = 1\n[[script.contacts]]\nname = \"f\"\n"
                    "shape = \"circle\"\nkeys = [{t = 0, pos = [1, 1]}, {t = 2, pos = [2, 1]}]\n"),
            "inline.toml:2:12: duration 1 s ends before the last keyframe at 2 s");
}

// a level file and a TUIO recording beside it, in a fresh folder
struct TuioLevel {
  std::string dir;
  std::string level;
  TuioLevel(const std::string& name, const std::string& toml, const std::string& xml) {
    dir = (std::filesystem::temp_directory_path() / ("pg_read_script_" + name)).string();
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    level = dir + "/level.toml";
    std::ofstream(level) << toml;
    if (!xml.empty()) std::ofstream(dir + "/stream.xml") << xml;
  }
  ~TuioLevel() { std::filesystem::remove_all(dir); }
};

// two TUIO 1.1 packets of touchlib's form: a cursor set, then an empty alive
constexpr const char* kTwoPackets = R"(<OSCPackets>
  <OSCPACKET ADDRESS="127.0.0.1" PORT="3333" TIME="1">
    <MESSAGE NAME="/tuio/2Dcur">
      <ARGUMENT TYPE="s" VALUE="set"/><ARGUMENT TYPE="i" VALUE="4"/>
      <ARGUMENT TYPE="f" VALUE="0.5"/><ARGUMENT TYPE="f" VALUE="0.5"/>
      <ARGUMENT TYPE="f" VALUE="0"/><ARGUMENT TYPE="f" VALUE="0"/><ARGUMENT TYPE="f" VALUE="0"/>
    </MESSAGE>
    <MESSAGE NAME="/tuio/2Dcur"><ARGUMENT TYPE="s" VALUE="alive"/><ARGUMENT TYPE="i" VALUE="4"/></MESSAGE>
    <MESSAGE NAME="/tuio/2Dcur"><ARGUMENT TYPE="s" VALUE="fseq"/><ARGUMENT TYPE="i" VALUE="1"/></MESSAGE>
  </OSCPACKET>
  <OSCPACKET ADDRESS="127.0.0.1" PORT="3333" TIME="1">
    <MESSAGE NAME="/tuio/2Dcur"><ARGUMENT TYPE="s" VALUE="alive"/></MESSAGE>
    <MESSAGE NAME="/tuio/2Dcur"><ARGUMENT TYPE="s" VALUE="fseq"/><ARGUMENT TYPE="i" VALUE="2"/></MESSAGE>
  </OSCPACKET>
</OSCPackets>
)";

TEST(LevelScript, ATuioStreamIsReadAtLoadAndSetsTheDefaultDuration) {
  const TuioLevel t("ok", "[script]\ntuio = \"stream.xml\"\n", kTwoPackets);
  const Result<Level> level = LoadLevel(t.level);
  ASSERT_TRUE(level.ok()) << level.error().Format();
  const Script& s = level.value().script;
  EXPECT_EQ(s.tuio, t.dir + "/stream.xml");
  ASSERT_TRUE(s.tuioBundles);
  EXPECT_EQ(s.tuioBundles->size(), 2u);
  // packets at 0 and 1/60 s ("immediately": one a frame), + 0.5 s timeout + 1 s to settle
  EXPECT_NEAR(s.duration, 1.0 / 60 + 0.5 + 1.0, 1e-9);
}

TEST(LevelErrors, ABadTuioStreamIsAnErrorAtItsKey) {
  {
    const TuioLevel t("missing", "[script]\ntuio = \"nope.xml\"\n", "");
    const Result<Level> level = LoadLevel(t.level);
    ASSERT_FALSE(level.ok());
    EXPECT_THAT(level.error().Format(),
                ::testing::StartsWith(t.level + ":2:8: TUIO stream 'nope.xml' not found"));
  }
  {
    // the XML's own error, at its line and column, after the level's key
    const TuioLevel t("broken", "[script]\ntuio = \"stream.xml\"\n",
                      "<OSCPackets>\n  <OSCPACKET TIME=\"1\">\n    <MESSAGE>\n");
    const Result<Level> level = LoadLevel(t.level);
    ASSERT_FALSE(level.ok());
    EXPECT_THAT(level.error().Format(), ::testing::StartsWith(t.level + ":2:8: TUIO stream"));
    EXPECT_THAT(level.error().Format(), ::testing::HasSubstr(t.dir + "/stream.xml:3:"));
  }
  {
    const TuioLevel t("both",
                      "[script]\ntuio = \"stream.xml\"\n[[script.contacts]]\nname = \"f\"\n"
                      "shape = \"circle\"\nkeys = [{t = 0, pos = [1, 1]}]\n",
                      kTwoPackets);
    const Result<Level> level = LoadLevel(t.level);
    ASSERT_FALSE(level.ok());
    EXPECT_EQ(level.error().Format(), t.level +
                                          ":2:8: a TUIO stream replaces the script's contacts: "
                                          "give one or the other");
  }
  EXPECT_EQ(ErrorOf("[script]\ntuio = \"\"\n"), "inline.toml:2:8: tuio is empty");
}

}  // namespace
}  // namespace pg
