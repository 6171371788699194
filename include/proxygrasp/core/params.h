// Parameter reflection. Every tunable struct has a Describe(Params&, ParamVisitor&) function that
// names each field with its key, range, unit and one-line doc. The level loader, `--set`, the
// tuning panel, "Copy as TOML" and docs/levels.md all walk the same description, so a parameter
// has one name in code, in TOML and in the docs.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/core/geometry.h"

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace pg {

/// When a change of a parameter takes effect on a running simulation.
enum class Apply {
  kLive,     ///< between two frames: the stage that owns it changes in place (SetParams)
  kRestart,  ///< only in a new run: the parameter shapes what the stage built
};
inline constexpr const char* kApplyNames[] = {"live", "restart"};

/// A field's one-line doc and when a change of it takes effect. A plain string is a live field's
/// doc: `"gravity for table friction"`, `{"layer count K", Apply::kRestart}`.
struct FieldDoc {
  FieldDoc(const char* text) : text(text) {}  // NOLINT(google-explicit-constructor)
  FieldDoc(const char* text, Apply apply) : text(text), apply(apply) {}
  const char* text;
  Apply apply = Apply::kLive;
};

/// Receives the fields of a parameter struct, by reference, one call each.
class ParamVisitor {
 public:
  virtual ~ParamVisitor() = default;

  /// A real number in [min, max]. unit is "cm", "g", "dyn", "s", "Hz", "deg", "1" (none), ...
  virtual void Real(const char* key, double& value, double min, double max, const char* unit,
                    FieldDoc doc) = 0;
  /// An integer in [min, max].
  virtual void Integer(const char* key, int& value, int min, int max, const char* unit,
                       FieldDoc doc) = 0;
  /// A flag.
  virtual void Boolean(const char* key, bool& value, FieldDoc doc) = 0;
  /// One of a fixed list of names; value is the index into names.
  virtual void Choice(const char* key, int& value, std::span<const char* const> names,
                      FieldDoc doc) = 0;
  /// Free text (a file path, say).
  virtual void Text(const char* key, std::string& value, FieldDoc doc) = 0;
  /// An angle held in radians and written in degrees, in [minDeg, maxDeg]; unit is "deg" or
  /// "deg/s". By default it is visited as a Real in degrees, so visitors that only know Real see
  /// and set degrees.
  virtual void Angle(const char* key, double& radians, double minDeg, double maxDeg,
                     const char* unit, FieldDoc doc);
  /// A 2D vector written [x, y], each component in [min, max]. Skipped by default.
  virtual void Vector(const char* key, Vec2& value, double min, double max, const char* unit,
                      FieldDoc doc);
  /// A list of 2D points written [[x, y], ...], each coordinate in [min, max]. Skipped by default.
  virtual void Points(const char* key, std::vector<Vec2>& value, double min, double max,
                      const char* unit, FieldDoc doc);
};

/// Visits an enum field as a Choice; E's values must be 0..names.size()-1 in order.
template <typename E>
void VisitEnum(ParamVisitor& v, const char* key, E& value, std::span<const char* const> names,
               FieldDoc doc) {
  int index = static_cast<int>(value);
  v.Choice(key, index, names, doc);
  value = static_cast<E>(index);
}

/// A named parameter table: the TOML section name and a function that describes the struct.
struct ParamSection {
  std::string name;                             ///< TOML table name, e.g. "physics"
  std::function<void(ParamVisitor&)> describe;  ///< visits the live struct's fields
};

/// What one field is, for listings, docs and validation.
struct FieldInfo {
  enum class Type { kReal, kInteger, kBoolean, kChoice, kText, kVector, kPoints };
  std::string key;
  Type type = Type::kReal;
  double min = 0.0;
  double max = 0.0;
  std::string unit;
  std::string doc;
  Apply apply = Apply::kLive;        ///< when a change takes effect
  std::vector<std::string> choices;  ///< for kChoice
  std::string value;                 ///< current value as TOML text
};

/// Lists a section's fields with their current values.
std::vector<FieldInfo> ListFields(const ParamSection& section);

/// Sets a field from text ("0.3", "true", "raycast", "\"path\"" or path, "[1, 2]", "[[0, 0], [1,
/// 0]]"). Unknown keys get a "did you mean" hint; values out of range name the allowed range.
/// Nothing changes on error.
MaybeError SetFieldFromText(const ParamSection& section, const std::string& key,
                            const std::string& text);

/// Checks every field of a section against its description: numbers (NaN included) and points
/// within their range, choices among their names. The first problem is an Error
/// "section.key must be in [min, max] unit (got value)"; nullopt when every field is valid.
MaybeError CheckFields(const ParamSection& section);

/// The keys of the fields whose values differ between two descriptions of the same struct (exact
/// values, as ListFields writes them), in description order.
std::vector<std::string> ChangedKeys(const ParamSection& a, const ParamSection& b);

/// The keys of the fields marked Apply::kRestart whose values differ between two descriptions of
/// the same struct, in description order: the changes a running stage cannot take.
std::vector<std::string> RestartKeysChanged(const ParamSection& a, const ParamSection& b);

/// Writes the fields whose values differ from `defaults` as a TOML table ("[name]\nkey = value\n"),
/// or "" when none differ.
std::string ChangedFieldsAsToml(const ParamSection& current, const ParamSection& defaults);

/// CheckFields for a value of a struct P that has a `Describe(P&, ParamVisitor&)`: the first value
/// out of its described range, as "section.key must be in ...".
template <typename P>
MaybeError CheckDescribed(const std::string& section, const P& params) {
  P copy = params;
  return CheckFields({section, [&copy](ParamVisitor& v) { Describe(copy, v); }});
}

/// RestartKeysChanged for two values of a struct P that has a `Describe(P&, ParamVisitor&)`.
template <typename P>
std::vector<std::string> RestartKeysChanged(const std::string& section, const P& now,
                                            const P& next) {
  P a = now;
  P b = next;
  return RestartKeysChanged({section, [&a](ParamVisitor& v) { Describe(a, v); }},
                            {section, [&b](ParamVisitor& v) { Describe(b, v); }});
}

/// The TOML spelling of a field type, for messages ("a number", "an integer", ...).
const char* TypeName(FieldInfo::Type type);

}  // namespace pg
