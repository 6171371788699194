// Reading level TOML: source locations, type names, the checked reader of a described table
// (TableReader), "did you mean" hints and small text helpers shared by the level builders.
// Private to the level module.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"
#include "proxygrasp/core/params.h"
#include "proxygrasp/core/text.h"

#include <toml++/toml.h>

#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pg::levelfile {

using Errors = std::vector<Error>;

// arrays of tables that an including file appends to its include's, rather than replacing them
inline constexpr const char* kTopArrays[] = {"objects", "expect", "goals", "variants"};

inline constexpr const char* kTopKeys[] = {
    "include",  "name",   "description", "table",  "physics", "proxies", "sensing",
    "tracking", "camera", "objects",     "script", "expect",  "goals",   "variants"};

inline constexpr const char* kParamTables[] = {"table",   "physics",  "proxies",
                                               "sensing", "tracking", "camera"};

bool IsTopArray(std::string_view key);

// the name of a TOML value's type, for messages
std::string TomlTypeName(const toml::node& n);

SourceLoc Loc(const toml::source_region& r);

std::string UnitSuffix(const char* unit);

std::string RangeText(double min, double max);

// "[a, b]" rounded to a thousandth, enough for a footprint in cm
std::string Span(double a, double b);

std::string VecText(const Vec2& v);

std::string JoinNames(std::span<const char* const> names);

std::optional<double> AsNumber(const toml::node& n);

// reads [x, y]; on failure says what is wrong
std::optional<Vec2> AsVec(const toml::node& n);

// keys of earlier versions of the format and the keys that replaced them
inline constexpr std::pair<const char*, const char*> kRenamedKeys[] = {
    {"angle_deg", "angle"},                                // goals
    {"tolerance_deg", "tolerance"}, {"min_deg", "above"},  // rotation expectations
    {"max_deg", "below"},           {"value", "held"},     // held expectations
};

// " (did you mean 'x'?)" for a renamed key, a near miss, or a known key the name is the start of
// ("angle" -> "angle_x")
std::string Hint(std::string_view name, const std::vector<std::string>& known);

bool InBox(const Vec2& v, double min, double max);

// reads the keys a ParamVisitor description knows from one TOML table, checking type and range;
// a key it does not know is left for the caller to report
class TableReader final : public ParamVisitor {
 public:
  TableReader(const toml::table& table, std::string prefix)
      : m_table(table), m_prefix(std::move(prefix)) {}

  std::vector<std::string> known;  ///< every key the description visits, in its order
  std::set<std::string> bad;       ///< keys whose value was rejected
  Errors errors;

  void Real(const char* key, double& value, double min, double max, const char* unit,
            FieldDoc) override {
    const toml::node* n = Find(key);
    if (!n) return;
    const auto v = AsNumber(*n);
    if (!v) return Fail(key, *n, "must be a number, got " + TomlTypeName(*n));
    // written so that NaN fails too
    if (!(*v >= min && *v <= max)) {
      return Fail(key, *n,
                  "must be in " + RangeText(min, max) + UnitSuffix(unit) + " (got " +
                      FormatDouble(*v) + ")");
    }
    value = *v;
  }
  void Integer(const char* key, int& value, int min, int max, const char* unit, FieldDoc) override {
    const toml::node* n = Find(key);
    if (!n) return;
    const auto* i = n->as_integer();
    if (!i) return Fail(key, *n, "must be an integer, got " + TomlTypeName(*n));
    if (i->get() < min || i->get() > max) {
      return Fail(key, *n,
                  "must be in " + RangeText(min, max) + UnitSuffix(unit) + " (got " +
                      std::to_string(i->get()) + ")");
    }
    value = static_cast<int>(i->get());
  }
  void Boolean(const char* key, bool& value, FieldDoc) override {
    const toml::node* n = Find(key);
    if (!n) return;
    const auto* b = n->as_boolean();
    if (!b) return Fail(key, *n, "must be true or false, got " + TomlTypeName(*n));
    value = b->get();
  }
  void Choice(const char* key, int& value, std::span<const char* const> names, FieldDoc) override {
    const toml::node* n = Find(key);
    if (!n) return;
    const auto* s = n->as_string();
    if (!s) {
      return Fail(key, *n, "must be one of " + JoinNames(names) + ", got " + TomlTypeName(*n));
    }
    for (size_t i = 0; i < names.size(); ++i) {
      if (s->get() == names[i]) {
        value = static_cast<int>(i);
        return;
      }
    }
    const std::vector<std::string> candidates(names.begin(), names.end());
    Fail(
        key, *n,
        "'" + s->get() + "' is not one of: " + JoinNames(names) + DidYouMean(s->get(), candidates));
  }
  void Text(const char* key, std::string& value, FieldDoc) override {
    const toml::node* n = Find(key);
    if (!n) return;
    const auto* s = n->as_string();
    if (!s) return Fail(key, *n, "must be a string, got " + TomlTypeName(*n));
    value = s->get();
  }
  void Vector(const char* key, Vec2& value, double min, double max, const char* unit,
              FieldDoc) override {
    const toml::node* n = Find(key);
    if (!n) return;
    const auto v = AsVec(*n);
    if (!v) return Fail(key, *n, "must be an array of two numbers [x, y]");
    if (!InBox(*v, min, max)) {
      return Fail(key, *n,
                  "must have each coordinate in " + RangeText(min, max) + UnitSuffix(unit) +
                      " (got " + VecText(*v) + ")");
    }
    value = *v;
  }
  void Points(const char* key, std::vector<Vec2>& value, double min, double max, const char* unit,
              FieldDoc) override {
    const toml::node* n = Find(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a) return Fail(key, *n, "must be an array of points [[x, y], ...]");
    std::vector<Vec2> points;
    for (const toml::node& item : *a) {
      const auto v = AsVec(item);
      if (!v) return Fail(key, item, "must be an array of points [[x, y], ...]");
      if (!InBox(*v, min, max)) {
        return Fail(key, item,
                    "must have each coordinate in " + RangeText(min, max) + UnitSuffix(unit) +
                        " (got " + VecText(*v) + ")");
      }
      points.push_back(*v);
    }
    value = std::move(points);
  }

 private:
  const toml::node* Find(const char* key) {
    known.emplace_back(key);
    return m_table.get(key);
  }
  void Fail(const char* key, const toml::node& at, const std::string& problem) {
    bad.insert(key);
    errors.push_back(MakeError(Loc(at.source()), m_prefix + key + " " + problem));
  }

  const toml::table& m_table;
  std::string m_prefix;
};

/// The keys of t that do not apply to its shape (applies(key) is false), each an error "'k' does
/// not apply to a <shapeText> (its size keys: <sizeKeys>)"; and, when the shape needs an outline
/// and t gives none, a missing "a <thingText> needs 'points'" at the table.
template <typename Applies>
void CheckShapeKeys(const toml::table& t, Applies applies, const std::string& shapeText,
                    const std::string& thingText, const std::string& sizeKeys, Errors& errors,
                    Errors& missing) {
  for (auto&& [k, v] : t) {
    if (applies(k.str())) continue;
    errors.push_back(MakeError(Loc(k.source()), "'" + std::string(k.str()) +
                                                    "' does not apply to a " + shapeText +
                                                    " (its size keys: " + sizeKeys + ")"));
  }
  if (applies("points") && !t.contains("points")) {
    missing.push_back(
        MakeError(Loc(t.source()), "a " + thingText + " needs 'points', its outline"));
  }
}

}  // namespace pg::levelfile
