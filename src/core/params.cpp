#include "proxygrasp/core/params.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"

#include <cassert>
#include <charconv>
#include <cmath>
#include <optional>

namespace pg {

void ParamVisitor::Angle(const char* key, double& radians, double minDeg, double maxDeg,
                         const char* unit, FieldDoc doc) {
  // visit in degrees; write back only a changed value so an untouched angle keeps every bit
  const double before = RadToDeg(radians);
  double degrees = before;
  Real(key, degrees, minDeg, maxDeg, unit, doc);
  if (degrees != before) radians = DegToRad(degrees);
}

void ParamVisitor::Vector(const char*, Vec2&, double, double, const char*, FieldDoc) {}

void ParamVisitor::Points(const char*, std::vector<Vec2>&, double, double, const char*, FieldDoc) {}

namespace {

std::string FormatVec(const Vec2& v) {
  return "[" + FormatDouble(v.x()) + ", " + FormatDouble(v.y()) + "]";
}

std::string FormatPoints(const std::vector<Vec2>& points) {
  std::string s = "[";
  for (size_t i = 0; i < points.size(); ++i) s += (i ? ", " : "") + FormatVec(points[i]);
  return s + "]";
}

std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// collects FieldInfo for every field
class Lister final : public ParamVisitor {
 public:
  std::vector<FieldInfo> fields;

  void Real(const char* key, double& value, double min, double max, const char* unit,
            FieldDoc doc) override {
    Add(key, FieldInfo::Type::kReal, min, max, unit, doc, FormatDouble(value));
  }
  void Integer(const char* key, int& value, int min, int max, const char* unit,
               FieldDoc doc) override {
    Add(key, FieldInfo::Type::kInteger, min, max, unit, doc, std::to_string(value));
  }
  void Boolean(const char* key, bool& value, FieldDoc doc) override {
    Add(key, FieldInfo::Type::kBoolean, 0, 1, "", doc, value ? "true" : "false");
  }
  void Choice(const char* key, int& value, std::span<const char* const> names,
              FieldDoc doc) override {
    Add(key, FieldInfo::Type::kChoice, 0, static_cast<double>(names.size()) - 1, "", doc,
        Quote(names[static_cast<size_t>(value)]));
    for (const char* n : names) fields.back().choices.emplace_back(n);
  }
  void Text(const char* key, std::string& value, FieldDoc doc) override {
    Add(key, FieldInfo::Type::kText, 0, 0, "", doc, Quote(value));
  }
  void Vector(const char* key, Vec2& value, double min, double max, const char* unit,
              FieldDoc doc) override {
    Add(key, FieldInfo::Type::kVector, min, max, unit, doc, FormatVec(value));
  }
  void Points(const char* key, std::vector<Vec2>& value, double min, double max, const char* unit,
              FieldDoc doc) override {
    Add(key, FieldInfo::Type::kPoints, min, max, unit, doc, FormatPoints(value));
  }

 private:
  void Add(const char* key, FieldInfo::Type type, double min, double max, const char* unit,
           FieldDoc doc, std::string value) {
    FieldInfo f;
    f.key = key;
    f.type = type;
    f.min = min;
    f.max = max;
    f.unit = unit;
    f.doc = doc.text;
    f.apply = doc.apply;
    f.value = std::move(value);
    fields.push_back(std::move(f));
  }
};

std::optional<double> ParseReal(const std::string& text) {
  double v = 0.0;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

// splits "[a, b, ...]" into its top-level items; nullopt when the brackets do not balance
std::optional<std::vector<std::string>> SplitArray(const std::string& text) {
  std::string t;
  for (char c : text) {
    if (c != ' ' && c != '\t') t += c;
  }
  if (t.size() < 2 || t.front() != '[' || t.back() != ']') return std::nullopt;
  std::vector<std::string> items;
  std::string item;
  int depth = 0;
  for (size_t i = 1; i + 1 < t.size(); ++i) {
    const char c = t[i];
    if (c == '[') ++depth;
    if (c == ']' && --depth < 0) return std::nullopt;
    if (c == ',' && depth == 0) {
      items.push_back(item);
      item.clear();
    } else {
      item += c;
    }
  }
  if (depth != 0) return std::nullopt;
  if (!item.empty() || !items.empty()) items.push_back(item);
  return items;
}

std::optional<Vec2> ParseVec(const std::string& text) {
  const auto items = SplitArray(text);
  if (!items || items->size() != 2) return std::nullopt;
  const auto x = ParseReal((*items)[0]);
  const auto y = ParseReal((*items)[1]);
  if (!x || !y) return std::nullopt;
  return Vec2(*x, *y);
}

bool InRange(const Vec2& v, double min, double max) {
  return v.x() >= min && v.x() <= max && v.y() >= min && v.y() <= max;
}

std::string Unquote(const std::string& text) {
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"') {
    return text.substr(1, text.size() - 2);
  }
  return text;
}

std::string RangeText(double min, double max) {
  return "[" + FormatDouble(min) + ", " + FormatDouble(max) + "]";
}

// sets one named field from text, recording the first problem
class Setter final : public ParamVisitor {
 public:
  Setter(std::string key, std::string text) : m_key(std::move(key)), m_text(std::move(text)) {}

  bool found = false;
  std::optional<std::string> problem;

  void Real(const char* key, double& value, double min, double max, const char* unit,
            FieldDoc) override {
    if (!Match(key)) return;
    const auto v = ParseReal(m_text);
    if (!v) {
      problem = "expected a number, got '" + m_text + "'";
    } else if (*v < min || *v > max) {
      problem = "value " + m_text + " is out of range " + RangeText(min, max) + " " + unit;
    } else {
      value = *v;
    }
  }
  void Integer(const char* key, int& value, int min, int max, const char*, FieldDoc) override {
    if (!Match(key)) return;
    int v = 0;
    const char* end = m_text.data() + m_text.size();
    auto [ptr, ec] = std::from_chars(m_text.data(), end, v);
    if (ec != std::errc() || ptr != end) {
      problem = "expected an integer, got '" + m_text + "'";
    } else if (v < min || v > max) {
      problem = "value " + m_text + " is out of range " + RangeText(min, max);
    } else {
      value = v;
    }
  }
  void Boolean(const char* key, bool& value, FieldDoc) override {
    if (!Match(key)) return;
    if (m_text == "true") {
      value = true;
    } else if (m_text == "false") {
      value = false;
    } else {
      problem = "expected true or false, got '" + m_text + "'";
    }
  }
  void Choice(const char* key, int& value, std::span<const char* const> names, FieldDoc) override {
    if (!Match(key)) return;
    const std::string name = Unquote(m_text);
    std::string allowed;
    for (size_t i = 0; i < names.size(); ++i) {
      if (name == names[i]) {
        value = static_cast<int>(i);
        return;
      }
      allowed += (i ? ", " : "") + std::string(names[i]);
    }
    problem = "'" + name + "' is not one of: " + allowed;
  }
  void Text(const char* key, std::string& value, FieldDoc) override {
    if (!Match(key)) return;
    value = Unquote(m_text);
  }
  void Vector(const char* key, Vec2& value, double min, double max, const char* unit,
              FieldDoc) override {
    if (!Match(key)) return;
    const auto v = ParseVec(m_text);
    if (!v) {
      problem = "expected [x, y], got '" + m_text + "'";
    } else if (!InRange(*v, min, max)) {
      problem = "value " + m_text + " is out of range " + RangeText(min, max) + " " + unit;
    } else {
      value = *v;
    }
  }
  void Points(const char* key, std::vector<Vec2>& value, double min, double max, const char* unit,
              FieldDoc) override {
    if (!Match(key)) return;
    const auto items = SplitArray(m_text);
    std::vector<Vec2> points;
    for (size_t i = 0; items && i < items->size(); ++i) {
      const auto v = ParseVec((*items)[i]);
      if (!v) break;
      points.push_back(*v);
    }
    if (!items || points.size() != items->size()) {
      problem = "expected [[x, y], ...], got '" + m_text + "'";
      return;
    }
    for (const Vec2& p : points) {
      if (!InRange(p, min, max)) {
        problem = "point " + FormatVec(p) + " is out of range " + RangeText(min, max) + " " + unit;
        return;
      }
    }
    value = std::move(points);
  }

 private:
  bool Match(const char* key) {
    if (m_key != key) return false;
    found = true;
    return true;
  }
  std::string m_key;
  std::string m_text;
};

// checks each field against its description, recording the first problem
class RangeChecker final : public ParamVisitor {
 public:
  std::optional<std::string> problem;  ///< "key must be in ..."

  void Real(const char* key, double& value, double min, double max, const char* unit,
            FieldDoc) override {
    // written so that NaN fails too
    if (!(value >= min && value <= max)) {
      Fail(key, "must be in " + RangeText(min, max) + UnitSuffix(unit) + " (got " +
                    FormatDouble(value) + ")");
    }
  }
  void Integer(const char* key, int& value, int min, int max, const char* unit, FieldDoc) override {
    if (value < min || value > max) {
      Fail(key, "must be in " + RangeText(min, max) + UnitSuffix(unit) + " (got " +
                    std::to_string(value) + ")");
    }
  }
  void Boolean(const char*, bool&, FieldDoc) override {}
  void Choice(const char* key, int& value, std::span<const char* const> names, FieldDoc) override {
    if (value < 0 || value >= static_cast<int>(names.size())) {
      std::string allowed;
      for (size_t i = 0; i < names.size(); ++i) allowed += (i ? ", " : "") + std::string(names[i]);
      Fail(key, "must be one of " + allowed + " (got index " + std::to_string(value) + ")");
    }
  }
  void Text(const char*, std::string&, FieldDoc) override {}
  void Vector(const char* key, Vec2& value, double min, double max, const char* unit,
              FieldDoc) override {
    if (!InRange(value, min, max)) {
      Fail(key, "must have each coordinate in " + RangeText(min, max) + UnitSuffix(unit) +
                    " (got " + FormatVec(value) + ")");
    }
  }
  void Points(const char* key, std::vector<Vec2>& value, double min, double max, const char* unit,
              FieldDoc) override {
    for (const Vec2& p : value) {
      if (!InRange(p, min, max)) {
        Fail(key, "must have each coordinate in " + RangeText(min, max) + UnitSuffix(unit) +
                      " (got " + FormatVec(p) + ")");
        return;
      }
    }
  }

 private:
  static std::string UnitSuffix(const char* unit) {
    const std::string u = unit ? unit : "";
    return (u.empty() || u == "1") ? std::string() : " " + u;
  }
  void Fail(const char* key, std::string what) {
    if (!problem) problem = std::string(key) + " " + std::move(what);
  }
};

}  // namespace

MaybeError CheckFields(const ParamSection& section) {
  RangeChecker checker;
  section.describe(checker);
  if (checker.problem) return MakeError({}, section.name + "." + *checker.problem);
  return std::nullopt;
}

namespace {

// the keys whose values differ between two descriptions of one struct, of those fields that
// `counts` accepts
template <typename Pred>
std::vector<std::string> ChangedKeysWhere(const ParamSection& a, const ParamSection& b,
                                          Pred counts) {
  const std::vector<FieldInfo> before = ListFields(a);
  const std::vector<FieldInfo> after = ListFields(b);
  assert(before.size() == after.size() && "ChangedKeys compares two copies of one struct");
  std::vector<std::string> keys;
  for (size_t i = 0; i < before.size() && i < after.size(); ++i) {
    if (before[i].value != after[i].value && counts(before[i])) keys.push_back(before[i].key);
  }
  return keys;
}

}  // namespace

std::vector<std::string> ChangedKeys(const ParamSection& a, const ParamSection& b) {
  return ChangedKeysWhere(a, b, [](const FieldInfo&) { return true; });
}

std::vector<std::string> RestartKeysChanged(const ParamSection& a, const ParamSection& b) {
  return ChangedKeysWhere(a, b, [](const FieldInfo& f) { return f.apply == Apply::kRestart; });
}

std::vector<FieldInfo> ListFields(const ParamSection& section) {
  Lister lister;
  section.describe(lister);
  return lister.fields;
}

MaybeError SetFieldFromText(const ParamSection& section, const std::string& key,
                            const std::string& text) {
  // the setter writes a field only when its new value is valid, so nothing changes on error
  Setter setter(key, text);
  section.describe(setter);
  if (!setter.found) {
    std::vector<std::string> keys;
    for (const FieldInfo& f : ListFields(section)) keys.push_back(f.key);
    return MakeError({}, "unknown key '" + section.name + "." + key + "'" + DidYouMean(key, keys));
  }
  if (setter.problem) return MakeError({}, section.name + "." + key + ": " + *setter.problem);
  return std::nullopt;
}

std::string ChangedFieldsAsToml(const ParamSection& current, const ParamSection& defaults) {
  const std::vector<FieldInfo> now = ListFields(current);
  const std::vector<FieldInfo> base = ListFields(defaults);
  std::string out;
  for (size_t i = 0; i < now.size(); ++i) {
    if (i < base.size() && now[i].value == base[i].value) continue;
    out += now[i].key + " = " + now[i].value + "\n";
  }
  if (out.empty()) return out;
  return "[" + current.name + "]\n" + out;
}

const char* TypeName(FieldInfo::Type type) {
  switch (type) {
    case FieldInfo::Type::kReal:
      return "a number";
    case FieldInfo::Type::kInteger:
      return "an integer";
    case FieldInfo::Type::kBoolean:
      return "a boolean";
    case FieldInfo::Type::kChoice:
      return "one of the names";
    case FieldInfo::Type::kText:
      return "a string";
    case FieldInfo::Type::kVector:
      return "an array [x, y]";
    case FieldInfo::Type::kPoints:
      return "an array of points [[x, y], ...]";
  }
  return "a value";
}

}  // namespace pg
