#include "proxygrasp/tuio/touchlib_xml.h"

#include "real_data.h"

#include "proxygrasp/tuio/decoder.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

namespace pg {
namespace {

using ::testing::HasSubstr;

// float32 normalised coordinates on a 61 cm table are good to about 4e-6 cm
constexpr double kFloatTol = 1e-4;  // cm

// ---- the reader ----

TEST(TouchlibXml, ReadsPacketsMessagesAndArguments) {
  const std::string text =
      "<?xml version=\"1.0\"?>\r\n<!-- a comment <MESSAGE> -->\r\n<OSCPackets>\r\n"
      "  <OSCPACKET ADDRESS=\"127.0.0.1\" PORT=\"1062\" TIME=\"1\">\r\n"
      "    <MESSAGE NAME=\"/tuio/2Dcur\">\r\n"
      "      <ARGUMENT TYPE=\"s\" VALUE=\"set\"/>\r\n"
      "      <ARGUMENT TYPE=\"i\" VALUE=\"1847\"/>\r\n"
      "      <ARGUMENT TYPE=\"f\" VALUE=\"2.374053E-4\"/>\r\n"
      "      <ARGUMENT TYPE='d' VALUE='-0.5' />\r\n"
      "      <ARGUMENT TYPE=\"s\" VALUE=\"a &amp; &lt;b&gt; &quot;&#65;\"/>\r\n"
      "      <ARGUMENT TYPE=\"T\"/>\r\n"
      "    </MESSAGE>\r\n"
      "    <MESSAGE NAME=\"/tuio/2Dcur\"></MESSAGE>\r\n"
      "  </OSCPACKET>\r\n"
      "  <OSCPACKET TIME=\"4294967298\"/>\r\n"
      "</OSCPackets>\r\n";
  Result<std::vector<OscBundle>> r = ParseTouchlibXml(text, "t.xml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const std::vector<OscBundle>& packets = r.value();
  ASSERT_EQ(packets.size(), 2u);
  EXPECT_EQ(packets[0].time, (OscTimeTag{0, 1}));
  EXPECT_EQ(packets[1].time, (OscTimeTag{1, 2}));
  EXPECT_TRUE(packets[1].messages.empty());
  ASSERT_EQ(packets[0].messages.size(), 2u);
  const OscMessage& m = packets[0].messages[0];
  EXPECT_EQ(m.address, "/tuio/2Dcur");
  EXPECT_EQ(m.Types(), "sifdsT");
  EXPECT_EQ(m.args[0].s, "set");
  EXPECT_EQ(m.args[1].i, 1847);
  EXPECT_FLOAT_EQ(static_cast<float>(m.args[2].f), 2.374053E-4f);
  EXPECT_EQ(m.args[3].f, -0.5);
  EXPECT_EQ(m.args[4].s, "a & <b> \"A");
  EXPECT_TRUE(packets[0].messages[1].args.empty());
}

TEST(TouchlibXml, KeepsNonFiniteNumbersForTheDecoderToCount) {
  Result<std::vector<OscBundle>> r = ParseTouchlibXml(
      "<OSCPACKET><MESSAGE NAME=\"/a\"><ARGUMENT TYPE=\"f\" VALUE=\"NaN\"/></MESSAGE></OSCPACKET>",
      "t.xml");
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_TRUE(std::isnan(r.value()[0].messages[0].args[0].f));
}

TEST(TouchlibXml, ErrorsNameTheLineAndColumn) {
  struct Case {
    const char* text;
    const char* where;
    const char* message;
  };
  const Case cases[] = {
      {"<OSCPACKET>\n  <ARGUMENT TYPE=\"i\" VALUE=\"1\"/>\n</OSCPACKET>", "t.xml:2:3",
       "ARGUMENT outside a MESSAGE"},
      {"<MESSAGE NAME=\"/a\"/>", "t.xml:1:1", "MESSAGE outside an OSCPACKET"},
      {"<OSCPACKET>\n<MESSAGE NAME=\"/a\">\n <ARGUMENT TYPE=\"i\" VALUE=\"1.5\"/>", "t.xml:3:2",
       "VALUE \"1.5\" is not an int32"},
      {"<OSCPACKET><MESSAGE NAME=\"/a\"><ARGUMENT TYPE=\"i\" VALUE=\"99999999999\"/>", "t.xml:1:31",
       "is not an int32"},
      {"<OSCPACKET><MESSAGE NAME=\"/a\"><ARGUMENT TYPE=\"f\" VALUE=\"x\"/>", "t.xml:1:31",
       "VALUE \"x\" is not a number"},
      {"<OSCPACKET><MESSAGE NAME=\"/a\"><ARGUMENT TYPE=\"b\" VALUE=\"00\"/>", "t.xml:1:31",
       "unsupported ARGUMENT TYPE \"b\""},
      {"<OSCPACKET><MESSAGE NAME=\"/a\"><ARGUMENT VALUE=\"1\"/>", "t.xml:1:31",
       "ARGUMENT needs a one-letter TYPE"},
      {"<OSCPACKET><MESSAGE NAME=\"/a\"><ARGUMENT TYPE=\"i\"/>", "t.xml:1:31",
       "ARGUMENT of TYPE i needs a VALUE"},
      {"<OSCPACKET><MESSAGE NAME=\"a\">", "t.xml:1:12", "MESSAGE needs a NAME starting with '/'"},
      {"<OSCPACKET>\n<MESSAGE NAME=\"/a\">\n</OSCPACKET>", "t.xml:3:1",
       "</OSCPACKET> without its <OSCPACKET>"},
      {"<OSCPACKET>\n  <MESSAGE NAME=\"/a\">", "t.xml:2:3", "MESSAGE is never closed"},
      {"\n\n <OSCPACKET>", "t.xml:3:2", "OSCPACKET is never closed"},
      {"<OSCPACKET TIME=\"soon\">", "t.xml:1:1", "TIME \"soon\" is not a time tag"},
      {"<OSCPACKET TIME=\"1>", "t.xml:1:12", "unterminated value of attribute TIME"},
      {"<OSCPACKET TIME=1>", "t.xml:1:17", "attribute TIME needs a quoted value"},
      {"<OSCPACKET\n  TIME", "t.xml:2:3", "attribute TIME needs a value"},
      {"<OSCPACKET A=\"&bogus;\">", "t.xml:1:12", "unknown entity &bogus;"},
      {"< OSCPACKET>", "t.xml:1:1", "expected a tag name after '<'"},
      {"<!-- never closed", "t.xml:1:1", "unterminated markup"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    Result<std::vector<OscBundle>> r = ParseTouchlibXml(c.text, "t.xml");
    ASSERT_FALSE(r.ok());
    EXPECT_THAT(r.error().Format(), HasSubstr(std::string(c.where) + ": "));
    EXPECT_THAT(r.error().message, HasSubstr(c.message));
  }
}

TEST(TouchlibXml, AMissingFileIsAnError) {
  Result<std::vector<OscBundle>> r = ReadTouchlibXml("/nonexistent/tuio.xml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().Format(), "/nonexistent/tuio.xml: cannot open the TUIO recording");
}

// ---- the recorded streams from a real table (../shared/real/touchlib) ----

using test::kNoRealData;
using test::RealDataDir;

// one cursor's life, read from the XML by hand (a script over the XML, not this reader): the
// packet it first appears in alive, the last such packet, the packet whose alive it has left,
// how many set messages it has, and its first and last normalised position
struct Session {
  TuioSessionId id;
  int first, last, lift, sets;
  double x0, y0, x1, y1;
};

struct Recording {
  const char* file;
  int packets;
  int64_t firstFseq;
  int sessions;
  int sets;
  int maxAlive;
  std::vector<Session> checked;
};

const Recording kRecordings[] = {
    {"touchlib/tuio_test.xml",
     546,
     53244,
     39,
     750,
     7,
     {{1847, 0, 187, 188, 188, 0.32171196, 0.55886567, 0.32262605, 0.566776},
      {1848, 35, 137, 138, 103, 0.3724041, 0.4086407, 0.45380107, 0.5567726},
      {1849, 36, 57, 58, 22, 0.0, 0.0, 0.0, 0.0},
      {1865, 203, 234, 235, 32, 0.2541643, 0.65127295, 0.35481566, 0.6140836},
      {1879, 248, 375, 376, 128, 0.424013, 0.3762815, 0.3059682, 0.6268407},
      {1887, 309, 377, 378, 69, 0.26926112, 0.68964726, 0.2704469, 0.6914832}}},
    {"touchlib/tuio_tableData.xml",
     373,
     497,
     12,
     257,
     2,
     {{9, 2, 42, 43, 41, 0.31734723, 0.3147611, 0.32947665, 0.59706515},
      {10, 85, 132, 133, 48, 0.5076447, 0.20842105, 0.52693856, 0.6198044},
      {11, 93, 128, 129, 36, 0.0, 1.0, 0.0, 1.0},
      {12, 154, 179, 180, 26, 0.72294974, 0.41473204, 0.67944705, 0.6492423},
      {13, 157, 160, 161, 4, 0.0, 1.0, 0.0, 1.0},
      {14, 162, 165, 166, 4, 0.0, 1.0, 0.0, 1.0},
      {15, 167, 177, 178, 11, 0.0, 1.0, 0.0, 1.0},
      {16, 203, 229, 230, 27, 0.29515514, 0.49067765, 0.4307044, 0.6411433},
      {17, 205, 229, 230, 25, 0.75292563, 0.46972466, 0.5867385, 0.6402787},
      {18, 246, 266, 267, 21, 0.422882, 0.3602147, 0.4185236, 0.50555587},
      {19, 250, 252, 253, 3, 0.0, 1.0, 0.0, 1.0},
      {20, 255, 265, 266, 11, 0.0, 1.0, 0.0, 1.0}}},
};

// names the recording in test names and failures instead of dumping its bytes
void PrintTo(const Recording& r, std::ostream* os) {
  *os << r.file;
}

const TuioContact* Find(const TuioFrame& f, TuioSessionId id) {
  for (const TuioContact& c : f.contacts)
    if (c.id == id) return &c;
  return nullptr;
}

Vec2 OnTable(const TuioParams& p, double x, double y) {
  return Vec2(x * p.table.width, (1.0 - y) * p.table.height);
}

class TouchlibReplay : public ::testing::TestWithParam<Recording> {};

TEST_P(TouchlibReplay, EveryCursorBecomesAContactAndLiftsWhenItLeavesAlive) {
  const Recording& rec = GetParam();
  const std::string dir = RealDataDir();
  if (dir.empty()) GTEST_SKIP() << kNoRealData;
  Result<std::vector<OscBundle>> r = ReadTouchlibXml(dir + "/" + rec.file);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const std::vector<OscBundle>& packets = r.value();
  ASSERT_EQ(static_cast<int>(packets.size()), rec.packets);

  const TuioParams params;
  TuioDecoder decoder(params);
  std::vector<TuioFrame> frames;
  for (size_t k = 0; k < packets.size(); ++k) {
    decoder.Decode(packets[k], k / 60.0);
    for (TuioFrame& f : decoder.TakeFrames()) frames.push_back(std::move(f));
  }
  EXPECT_EQ(decoder.stats().TotalDropped(), 0u) << decoder.stats().Summary();
  // every packet ends with its fseq: one frame each, numbered as the recording numbers them
  ASSERT_EQ(static_cast<int>(frames.size()), rec.packets);
  for (int k = 0; k < rec.packets; ++k) ASSERT_EQ(frames[k].frame, rec.firstFseq + k) << k;

  // every set message: the contact of that session is a fingertip at its position, that frame
  int sets = 0;
  std::set<TuioSessionId> sessions;
  size_t maxAlive = 0;
  for (int k = 0; k < rec.packets; ++k) {
    maxAlive = std::max(maxAlive, frames[k].contacts.size());
    for (const OscMessage& m : packets[k].messages) {
      if (m.args.size() < 4 || m.args[0].s != "set") continue;
      ++sets;
      sessions.insert(m.args[1].i);
      const TuioContact* c = Find(frames[k], m.args[1].i);
      ASSERT_NE(c, nullptr) << "session " << m.args[1].i << " in packet " << k;
      EXPECT_EQ(c->shape, TuioShape::kCursor);
      EXPECT_NEAR((c->centroid - OnTable(params, m.args[2].f, m.args[3].f)).norm(), 0.0, kFloatTol);
    }
  }
  EXPECT_EQ(sets, rec.sets);
  EXPECT_EQ(static_cast<int>(sessions.size()), rec.sessions);
  EXPECT_EQ(static_cast<int>(maxAlive), rec.maxAlive);

  // each session: new once, live until it leaves alive, then lifted once
  std::map<TuioSessionId, int> newCount, liftCount;
  for (const TuioFrame& f : frames) {
    for (const TuioContact& c : f.contacts)
      if (c.isNew) ++newCount[c.id];
    for (TuioSessionId id : f.lifted) ++liftCount[id];
  }
  for (TuioSessionId id : sessions) {
    EXPECT_EQ(newCount[id], 1) << id;
    EXPECT_EQ(liftCount[id], 1) << id;
  }
  EXPECT_TRUE(frames.back().contacts.empty()) << "every recording ends with an empty alive";

  // the sessions checked by hand against the XML
  for (const Session& s : rec.checked) {
    SCOPED_TRACE("session " + std::to_string(s.id));
    if (s.first > 0) {
      EXPECT_EQ(Find(frames[s.first - 1], s.id), nullptr);
    }
    const TuioContact* first = Find(frames[s.first], s.id);
    ASSERT_NE(first, nullptr);
    EXPECT_TRUE(first->isNew);
    EXPECT_NEAR((first->centroid - OnTable(params, s.x0, s.y0)).norm(), 0.0, kFloatTol);
    for (int k = s.first + 1; k <= s.last; ++k) {
      const TuioContact* c = Find(frames[k], s.id);
      ASSERT_NE(c, nullptr) << "frame " << k;
      EXPECT_FALSE(c->isNew);
    }
    EXPECT_NEAR((Find(frames[s.last], s.id)->centroid - OnTable(params, s.x1, s.y1)).norm(), 0.0,
                kFloatTol);
    EXPECT_EQ(Find(frames[s.lift], s.id), nullptr);
    EXPECT_NE(std::find(frames[s.lift].lifted.begin(), frames[s.lift].lifted.end(), s.id),
              frames[s.lift].lifted.end());
    int setCount = 0;
    for (const OscBundle& p : packets)
      for (const OscMessage& m : p.messages)
        if (m.args.size() >= 2 && m.args[0].s == "set" && m.args[1].i == s.id) ++setCount;
    EXPECT_EQ(setCount, s.sets);
  }
}

TEST_P(TouchlibReplay, ReplayTuioGivesTheSameFrames) {
  const Recording& rec = GetParam();
  const std::string dir = RealDataDir();
  if (dir.empty()) GTEST_SKIP() << kNoRealData;
  Result<std::vector<OscBundle>> r = ReadTouchlibXml(dir + "/" + rec.file);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  const std::vector<TuioFrame> frames = ReplayTuio(r.value(), TuioParams());
  ASSERT_EQ(static_cast<int>(frames.size()), rec.packets);
  EXPECT_NEAR(frames.back().time, (rec.packets - 1) / 60.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Recordings, TouchlibReplay, ::testing::ValuesIn(kRecordings),
                         [](const ::testing::TestParamInfo<Recording>& info) {
                           return info.index == 0 ? std::string("test") : std::string("tableData");
                         });

}  // namespace
}  // namespace pg
