#include "proxygrasp/core/params.h"

#include "proxygrasp/core/text.h"

#include <charconv>
#include <cmath>
#include <optional>

namespace pg {

namespace {

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
            const char* doc) override {
    Add(key, FieldInfo::Type::kReal, min, max, unit, doc, FormatDouble(value));
  }
  void Integer(const char* key, int& value, int min, int max, const char* unit,
               const char* doc) override {
    Add(key, FieldInfo::Type::kInteger, min, max, unit, doc, std::to_string(value));
  }
  void Boolean(const char* key, bool& value, const char* doc) override {
    Add(key, FieldInfo::Type::kBoolean, 0, 1, "", doc, value ? "true" : "false");
  }
  void Choice(const char* key, int& value, std::span<const char* const> names,
              const char* doc) override {
    Add(key, FieldInfo::Type::kChoice, 0, static_cast<double>(names.size()) - 1, "", doc,
        Quote(names[static_cast<size_t>(value)]));
    for (const char* n : names) fields.back().choices.emplace_back(n);
  }
  void Text(const char* key, std::string& value, const char* doc) override {
    Add(key, FieldInfo::Type::kText, 0, 0, "", doc, Quote(value));
  }

 private:
  void Add(const char* key, FieldInfo::Type type, double min, double max, const char* unit,
           const char* doc, std::string value) {
    FieldInfo f;
    f.key = key;
    f.type = type;
    f.min = min;
    f.max = max;
    f.unit = unit;
    f.doc = doc;
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
            const char*) override {
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
  void Integer(const char* key, int& value, int min, int max, const char*, const char*) override {
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
  void Boolean(const char* key, bool& value, const char*) override {
    if (!Match(key)) return;
    if (m_text == "true") {
      value = true;
    } else if (m_text == "false") {
      value = false;
    } else {
      problem = "expected true or false, got '" + m_text + "'";
    }
  }
  void Choice(const char* key, int& value, std::span<const char* const> names,
              const char*) override {
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
  void Text(const char* key, std::string& value, const char*) override {
    if (!Match(key)) return;
    value = Unquote(m_text);
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

}  // namespace

std::vector<FieldInfo> ListFields(const ParamSection& section) {
  Lister lister;
  section.describe(lister);
  return lister.fields;
}

Status SetFieldFromText(const ParamSection& section, const std::string& key,
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
  }
  return "a value";
}

}  // namespace pg
