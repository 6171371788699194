#include "toml_reader.h"

#include "proxygrasp/core/text.h"

#include <algorithm>
#include <cmath>

namespace pg::levelfile {

bool IsTopArray(std::string_view key) {
  return std::find(std::begin(kTopArrays), std::end(kTopArrays), key) != std::end(kTopArrays);
}

// the name of a TOML value's type, for messages
std::string TomlTypeName(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

SourceLoc Loc(const toml::source_region& r) {
  SourceLoc loc;
  if (r.path) loc.file = *r.path;
  loc.line = static_cast<int>(r.begin.line);
  loc.col = static_cast<int>(r.begin.column);
  return loc;
}

std::string UnitSuffix(const char* unit) {
  const std::string u = unit ? unit : "";
  return (u.empty() || u == "1") ? std::string() : " " + u;
}

std::string RangeText(double min, double max) {
  return "[" + FormatDouble(min) + ", " + FormatDouble(max) + "]";
}

// "[a, b]" rounded to a thousandth, enough for a footprint in cm
std::string Span(double a, double b) {
  auto round = [](double v) { return FormatDouble(std::round(v * 1000) / 1000 + 0.0); };
  return "[" + round(a) + ", " + round(b) + "]";
}

std::string VecText(const Vec2& v) {
  return "[" + FormatDouble(v.x()) + ", " + FormatDouble(v.y()) + "]";
}

std::string JoinNames(std::span<const char* const> names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + std::string(names[i]);
  return s;
}

std::optional<double> AsNumber(const toml::node& n) {
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = n.as_floating_point()) return f->get();
  return std::nullopt;
}

// reads [x, y]; on failure says what is wrong
std::optional<Vec2> AsVec(const toml::node& n) {
  const toml::array* a = n.as_array();
  if (!a || a->size() != 2) return std::nullopt;
  const auto x = AsNumber(*a->get(0));
  const auto y = AsNumber(*a->get(1));
  if (!x || !y) return std::nullopt;
  return Vec2(*x, *y);
}

// " (did you mean 'x'?)" for a renamed key, a near miss, or a known key the name is the start of
// ("angle" -> "angle_x")
std::string Hint(std::string_view name, const std::vector<std::string>& known) {
  for (const auto& [old, now] : kRenamedKeys) {
    if (name == old && std::find(known.begin(), known.end(), now) != known.end()) {
      return " (did you mean '" + std::string(now) + "'? '" + std::string(old) + "' was renamed)";
    }
  }
  const std::string close = DidYouMean(name, known);
  if (!close.empty()) return close;
  for (const std::string& k : known) {
    if (k.size() > name.size() && k.compare(0, name.size(), name) == 0 && k[name.size()] == '_') {
      return " (did you mean '" + k + "'?)";
    }
  }
  return {};
}

bool InBox(const Vec2& v, double min, double max) {
  return v.x() >= min && v.x() <= max && v.y() >= min && v.y() <= max;
}

}  // namespace pg::levelfile
