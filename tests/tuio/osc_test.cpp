#include "proxygrasp/tuio/osc.h"

#include <gtest/gtest.h>

#include <cmath>
#include <lo/lo.h>

namespace pg {
namespace {

// liblo's serialised length of the same message, to check the sizes the encoder relies on
size_t LoLength(const OscMessage& m) {
  lo_message lm = lo_message_new();
  for (const OscArg& a : m.args) {
    switch (a.type) {
      case 'i':
        lo_message_add_int32(lm, static_cast<int32_t>(a.i));
        break;
      case 'h':
        lo_message_add_int64(lm, a.i);
        break;
      case 'f':
        lo_message_add_float(lm, static_cast<float>(a.f));
        break;
      case 'd':
        lo_message_add_double(lm, a.f);
        break;
      case 's':
        lo_message_add_string(lm, a.s.c_str());
        break;
      case 't':
        lo_message_add_timetag(lm, lo_timetag{a.t.seconds, a.t.fraction});
        break;
      case 'T':
        lo_message_add_true(lm);
        break;
      default:
        ADD_FAILURE() << "type " << a.type << " not handled by the test";
    }
  }
  const size_t n = lo_message_length(lm, m.address.c_str());
  lo_message_free(lm);
  return n;
}

std::vector<OscMessage> Samples() {
  std::vector<OscMessage> out;
  out.push_back({"/a", {}});
  out.push_back({"/abc", {}});
  out.push_back({"/tuio2/alv", {}});
  out.push_back({"/tuio2/alv", {OscArg::Int(1), OscArg::Int(2), OscArg::Int(3)}});
  out.push_back({"/tuio2/frm",
                 {OscArg::Int(1), OscArg::Time({5, 6}), OscArg::Int(7), OscArg::String("abc")}});
  out.push_back({"/tuio/2Dcur",
                 {OscArg::String("set"), OscArg::Int(3), OscArg::Float(0.5f), OscArg::Double(0.25),
                  OscArg::Int64(9), OscArg::Other('T')}});
  out.push_back({"/x", {OscArg::String(""), OscArg::String("1234"), OscArg::String("12345678")}});
  return out;
}

TEST(Osc, MessageAndBundleSizesMatchLiblo) {
  for (const OscMessage& m : Samples()) EXPECT_EQ(OscMessageSize(m), LoLength(m)) << m.address;
  OscBundle b{OscTimeTag{1, 2}, Samples()};
  lo_bundle lb = lo_bundle_new(lo_timetag{1, 2});
  std::vector<lo_message> messages;
  for (const OscMessage& m : b.messages) {
    lo_message lm = lo_message_new();
    for (const OscArg& a : m.args) {
      if (a.type == 'i') lo_message_add_int32(lm, static_cast<int32_t>(a.i));
      if (a.type == 'h') lo_message_add_int64(lm, a.i);
      if (a.type == 'f') lo_message_add_float(lm, static_cast<float>(a.f));
      if (a.type == 'd') lo_message_add_double(lm, a.f);
      if (a.type == 's') lo_message_add_string(lm, a.s.c_str());
      if (a.type == 't') lo_message_add_timetag(lm, lo_timetag{a.t.seconds, a.t.fraction});
      if (a.type == 'T') lo_message_add_true(lm);
    }
    lo_bundle_add_message(lb, m.address.c_str(), lm);
  }
  EXPECT_EQ(OscBundleSize(b), lo_bundle_length(lb));
  lo_bundle_free_recursive(lb);
}

TEST(Osc, TimeTagsFromSeconds) {
  const OscTimeTag t = OscTimeTag::FromSeconds(12.5);
  EXPECT_EQ(t.seconds, 12u);
  EXPECT_EQ(t.fraction, 0x80000000u);
  EXPECT_DOUBLE_EQ(t.ToSeconds(), 12.5);
  EXPECT_EQ(OscTimeTag::FromSeconds(-3.0).seconds, 0u);
  EXPECT_EQ(OscTimeTag::FromSeconds(std::nan("")).seconds, 0u);
}

TEST(Osc, ArgumentKinds) {
  EXPECT_TRUE(OscArg::Int(1).IsInt());
  EXPECT_TRUE(OscArg::Int64(1).IsInt());
  EXPECT_TRUE(OscArg::Float(1).IsFloat());
  EXPECT_TRUE(OscArg::Double(1).IsFloat());
  EXPECT_TRUE(OscArg::String("a").IsString());
  EXPECT_FALSE(OscArg::Other('b').IsInt() || OscArg::Other('b').IsFloat() ||
               OscArg::Other('b').IsString());
}

TEST(Osc, FormatsAMessageOnOneLine) {
  const OscMessage m{"/tuio2/alv", {OscArg::Int(3), OscArg::Float(0.5f), OscArg::String("x")}};
  EXPECT_EQ(m.Types(), "ifs");
  EXPECT_EQ(FormatOscMessage(m), "/tuio2/alv ifs 3 0.5 \"x\"");
}

}  // namespace
}  // namespace pg
