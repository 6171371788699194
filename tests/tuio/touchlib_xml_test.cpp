#include "proxygrasp/tuio/touchlib_xml.h"

#include "real_data.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/tuio/decoder.h"
#include "proxygrasp/tuio/encoder.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <unistd.h>

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
      {"<OSCPACKET><MESSAGE NAME=\"/a\"><ARGUMENT TYPE=\"t\" VALUE=\"-1\"/>", "t.xml:1:31",
       "VALUE \"-1\" is not a time tag"},
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

// ---- the writer ----

// a file name in the temporary folder, unique to this process
std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("pg_touchlib_" + std::to_string(getpid()) + "_" + name))
      .string();
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// true when two numbers are the same bits (NaN equal to NaN, -0 apart from 0)
bool SameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// the bundles as the reader gives them back: every field, time tags included
void ExpectSameBundles(const std::vector<OscBundle>& got, const std::vector<OscBundle>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t b = 0; b < want.size(); ++b) {
    SCOPED_TRACE("bundle " + std::to_string(b));
    EXPECT_EQ(got[b].time, want[b].time);
    ASSERT_EQ(got[b].messages.size(), want[b].messages.size());
    for (size_t m = 0; m < want[b].messages.size(); ++m) {
      const OscMessage& g = got[b].messages[m];
      const OscMessage& w = want[b].messages[m];
      SCOPED_TRACE(FormatOscMessage(w));
      EXPECT_EQ(g.address, w.address);
      ASSERT_EQ(g.Types(), w.Types());
      for (size_t k = 0; k < w.args.size(); ++k) {
        const OscArg& x = g.args[k];
        const OscArg& y = w.args[k];
        SCOPED_TRACE("argument " + std::to_string(k));
        if (y.IsInt()) {
          EXPECT_EQ(x.i, y.i);
        } else if (y.type == 'f') {
          EXPECT_TRUE(SameBits(static_cast<float>(x.f), static_cast<float>(y.f)))
              << x.f << " vs " << y.f;
        } else if (y.type == 'd') {
          EXPECT_TRUE(SameBits(x.f, y.f)) << x.f << " vs " << y.f;
        } else if (y.IsString()) {
          EXPECT_EQ(x.s, y.s);
        } else if (y.type == 't') {
          EXPECT_EQ(x.t, y.t);
        }
      }
    }
  }
}

// writes the bundles to a file and reads them back
std::vector<OscBundle> WriteAndRead(const std::vector<OscBundle>& bundles,
                                    const std::string& name) {
  const std::string path = TempPath(name);
  {
    TouchlibXmlWriter writer;
    EXPECT_FALSE(writer.Open(path));
    for (const OscBundle& b : bundles) EXPECT_FALSE(writer.Append(b));
    EXPECT_EQ(writer.packets(), static_cast<int64_t>(bundles.size()));
    EXPECT_FALSE(writer.Close());
  }
  Result<std::vector<OscBundle>> r = ReadTouchlibXml(path);
  std::remove(path.c_str());
  EXPECT_TRUE(r.ok()) << r.error().Format();
  return r.ok() ? r.value() : std::vector<OscBundle>{};
}

TEST(TouchlibXmlWriter, EveryArgumentTypeAndTimeTagReadsBackEqual) {
  OscArg symbol = OscArg::String("sym<bol>");
  symbol.type = 'S';
  std::vector<OscBundle> bundles = {
      {OscTimeTag{0, 1},  // "immediately"
       {{"/ints",
         {OscArg::Int(0), OscArg::Int(std::numeric_limits<int32_t>::min()),
          OscArg::Int(std::numeric_limits<int32_t>::max()), OscArg::Int64(-1),
          OscArg::Int64(std::numeric_limits<int64_t>::min()),
          OscArg::Int64(std::numeric_limits<int64_t>::max())}},
        {"/floats",
         {OscArg::Float(0.1f), OscArg::Float(-0.0f), OscArg::Float(1.0f / 3.0f),
          OscArg::Float(std::numeric_limits<float>::denorm_min()),
          OscArg::Float(std::numeric_limits<float>::max()),
          OscArg::Float(std::numeric_limits<float>::quiet_NaN()),
          OscArg::Float(-std::numeric_limits<float>::infinity())}},
        {"/doubles",
         {OscArg::Double(0.1), OscArg::Double(1.0 / 3.0), OscArg::Double(-1e-300),
          OscArg::Double(std::numeric_limits<double>::denorm_min()),
          OscArg::Double(std::numeric_limits<double>::max()),
          OscArg::Double(std::numeric_limits<double>::infinity())}}}},
      {OscTimeTag::FromSeconds(12.345),
       {{"/strings",
         {OscArg::String("a & b < c > d \" e ' f"), OscArg::String("&amp; is not unescaped twice"),
          OscArg::String("tab\tnew\nline\r"), OscArg::String(""), OscArg::String("caf\xc3\xa9"),
          symbol}},
        {"/others",
         {OscArg::Time(OscTimeTag{3900000000u, 5}), OscArg::Other('T'), OscArg::Other('F'),
          OscArg::Other('N'), OscArg::Other('I'), OscArg::Time(OscTimeTag{0, 0})}},
        {"/no/args", {}}}},
      {OscTimeTag{0xffffffffu, 0xffffffffu}, {}},  // the largest time tag, no message
      {OscTimeTag{0, 0}, {{"/a&b<c>", {OscArg::Int(7)}}}},
  };
  ExpectSameBundles(WriteAndRead(bundles, "types.xml"), bundles);
}

TEST(TouchlibXmlWriter, WritesTouchlibsLayoutWithTheRawTimeTag) {
  const std::string path = TempPath("layout.xml");
  TouchlibXmlWriter writer;
  ASSERT_FALSE(writer.Open(path, "10.0.0.2", 3333));
  ASSERT_FALSE(writer.Append(
      {OscTimeTag{1, 2}, {{"/tuio/2Dcur", {OscArg::String("fseq"), OscArg::Int(7)}}}}));
  ASSERT_FALSE(writer.Close());
  EXPECT_FALSE(writer.Close()) << "closing twice is harmless";
  EXPECT_EQ(ReadText(path),
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<OSCPackets>\n"
            "  <OSCPACKET ADDRESS=\"10.0.0.2\" PORT=\"3333\" TIME=\"4294967298\">\n"
            "    <MESSAGE NAME=\"/tuio/2Dcur\">\n"
            "      <ARGUMENT TYPE=\"s\" VALUE=\"fseq\"/>\n"
            "      <ARGUMENT TYPE=\"i\" VALUE=\"7\"/>\n"
            "    </MESSAGE>\n"
            "  </OSCPACKET>\n"
            "</OSCPackets>\n");
  std::remove(path.c_str());
}

TEST(TouchlibXmlWriter, PacketsGoToDiskAsTheyComeAndTheDestructorEndsTheDocument) {
  const std::string path = TempPath("stream.xml");
  OscBundle bundle{OscTimeTag::FromSeconds(1.0), {{"/tuio2/alv", {OscArg::Int(3)}}}};
  {
    TouchlibXmlWriter writer;
    ASSERT_FALSE(writer.Open(path));
    // enough packets to pass any stdio buffer: the file grows while the writer is open
    for (int k = 0; k < 2000; ++k) ASSERT_FALSE(writer.Append(bundle));
    EXPECT_GT(std::filesystem::file_size(path), 100000u);
  }
  Result<std::vector<OscBundle>> r = ReadTouchlibXml(path);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  EXPECT_EQ(r.value().size(), 2000u);
  std::remove(path.c_str());
}

TEST(TouchlibXmlWriter, AnEmptyRecordingIsADocumentOfNoPackets) {
  EXPECT_TRUE(WriteAndRead({}, "empty.xml").empty());
}

TEST(TouchlibXmlWriter, EncodedFramesReplayAsTheSameFrames) {
  // three frames of two contours from the encoder (frm carries a time tag argument), the second
  // contour lifting in the last
  TuioEncoderParams params;
  params.cursors11 = true;
  TuioEncoder encoder(params);
  auto disc = [](TuioSessionId id, Vec2 c, double r) {
    TuioOutContact out;
    out.id = id;
    out.centroid = c;
    for (int k = 0; k < 40; ++k) {
      const double t = 2.0 * kPi * k / 40;
      out.contour.push_back(c + r * Vec2(std::cos(t), std::sin(t)));
    }
    return out;
  };
  std::vector<OscBundle> bundles;
  for (int f = 0; f < 3; ++f) {
    std::vector<TuioOutContact> contacts = {disc(4, Vec2(10 + f, 12), 1.0)};
    if (f < 2) contacts.push_back(disc(9, Vec2(40, 30 - f), 3.0));
    for (OscBundle& b : encoder.Encode(f, OscTimeTag::FromSeconds(f / 60.0), contacts))
      bundles.push_back(std::move(b));
  }
  const std::vector<OscBundle> back = WriteAndRead(bundles, "encoded.xml");
  ExpectSameBundles(back, bundles);
  const std::vector<TuioFrame> want = ReplayTuio(bundles, TuioParams());
  const std::vector<TuioFrame> got = ReplayTuio(back, TuioParams());
  ASSERT_EQ(got.size(), want.size());
  for (size_t f = 0; f < want.size(); ++f) {
    EXPECT_EQ(got[f].frame, want[f].frame);
    EXPECT_EQ(got[f].lifted, want[f].lifted);
    ASSERT_EQ(got[f].contacts.size(), want[f].contacts.size());
    for (size_t c = 0; c < want[f].contacts.size(); ++c) {
      EXPECT_EQ(got[f].contacts[c].id, want[f].contacts[c].id);
      EXPECT_EQ(got[f].contacts[c].isNew, want[f].contacts[c].isNew);
      EXPECT_EQ(got[f].contacts[c].contour, want[f].contacts[c].contour);
    }
  }
}

TEST(TouchlibXmlWriter, AFileThatCannotBeCreatedIsAnErrorNamingIt) {
  TouchlibXmlWriter writer;
  MaybeError e = writer.Open("/nonexistent/folder/out.xml");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->Format(),
            "/nonexistent/folder/out.xml: cannot create the TUIO recording: No such file or "
            "directory");
  EXPECT_FALSE(writer.IsOpen());
  // a folder where the file should be, and a file where a folder should be (root may write
  // anywhere else)
  const std::string dir = TempPath("a_folder");
  std::filesystem::create_directories(dir);
  e = writer.Open(dir);
  ASSERT_TRUE(e);
  EXPECT_THAT(e->Format(), HasSubstr(dir + ": cannot create the TUIO recording"));
  std::filesystem::remove(dir);
  const std::string file = TempPath("a_file");
  std::ofstream(file) << "x";
  e = writer.Open(file + "/out.xml");
  ASSERT_TRUE(e);
  EXPECT_THAT(e->Format(), HasSubstr(file + "/out.xml: cannot create the TUIO recording"));
  std::remove(file.c_str());
  EXPECT_THAT(writer.Append({}).value().message, HasSubstr("not open"));
}

TEST(TouchlibXmlWriter, ABundleItCannotHoldIsAnErrorAndLeavesNothingBehind) {
  const std::string path = TempPath("partial.xml");
  TouchlibXmlWriter writer;
  ASSERT_FALSE(writer.Open(path));
  const OscBundle good{OscTimeTag{0, 1}, {{"/ok", {OscArg::Int(1)}}}};
  ASSERT_FALSE(writer.Append(good));
  MaybeError e =
      writer.Append({OscTimeTag{0, 1},
                     {{"/ok", {OscArg::Int(2)}}, {"/blob", {OscArg::Int(1), OscArg::Other('b')}}}});
  ASSERT_TRUE(e);
  EXPECT_EQ(e->Format(), path +
                             ": /blob argument 1: type 'b' cannot be recorded (types i h f d s S "
                             "t T F N I)");
  e = writer.Append({OscTimeTag{0, 1}, {{"/nul", {OscArg::String(std::string("a\0b", 3))}}}});
  ASSERT_TRUE(e);
  EXPECT_THAT(e->message, HasSubstr("/nul argument 0: a string holding a NUL byte"));
  ASSERT_FALSE(writer.Close());
  Result<std::vector<OscBundle>> r = ReadTouchlibXml(path);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  ExpectSameBundles(r.value(), {good});
  std::remove(path.c_str());
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

TEST_P(TouchlibReplay, WrittenBackItReadsTheSamePackets) {
  const Recording& rec = GetParam();
  const std::string dir = RealDataDir();
  if (dir.empty()) GTEST_SKIP() << kNoRealData;
  Result<std::vector<OscBundle>> r = ReadTouchlibXml(dir + "/" + rec.file);
  ASSERT_TRUE(r.ok()) << r.error().Format();
  ExpectSameBundles(WriteAndRead(r.value(), "rewritten.xml"), r.value());
}

INSTANTIATE_TEST_SUITE_P(Recordings, TouchlibReplay, ::testing::ValuesIn(kRecordings),
                         [](const ::testing::TestParamInfo<Recording>& info) {
                           return info.index == 0 ? std::string("test") : std::string("tableData");
                         });

}  // namespace
}  // namespace pg
