// Level loading in three steps: read the TOML files (includes merged into one tree whose nodes keep
// their file:line:col), validate every key against the code's descriptions, and build the Level.
// The first error in processing order is returned; within one table the earliest in the file wins.
#include "proxygrasp/level/level.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/physics/shapes.h"
#include "proxygrasp/sensing/recorder.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace pg {

namespace fs = std::filesystem;

bool Region::Contains(const Vec2& p) const {
  if (kind == Kind::kCircle) return (p - center).squaredNorm() <= radius * radius;
  return p.x() >= min.x() && p.x() <= max.x() && p.y() >= min.y() && p.y() <= max.y();
}

bool Goal::IsMet(const Pose2& pose) const {
  if (zone && !zone->Contains(pose.pos)) return false;
  if (angle && std::abs(WrapAngle(pose.angle - *angle)) > tolerance) return false;
  return true;
}

const ObjectSpec* Level::FindObject(std::string_view objectName) const {
  for (const ObjectSpec& o : objects) {
    if (o.name == objectName) return &o;
  }
  return nullptr;
}

const Variant* Level::FindVariant(std::string_view variantName) const {
  for (const Variant& v : variants) {
    if (v.name == variantName) return &v;
  }
  return nullptr;
}

namespace {

using Errors = std::vector<Error>;

// arrays of tables that an including file appends to its include's, rather than replacing them
constexpr const char* kTopArrays[] = {"objects", "expect", "goals", "variants"};
constexpr const char* kTopKeys[] = {"include", "name",    "description", "table",   "physics",
                                    "proxies", "sensing", "tracking",    "camera",  "objects",
                                    "script",  "expect",  "goals",       "variants"};
constexpr const char* kParamTables[] = {"table",   "physics",  "proxies",
                                        "sensing", "tracking", "camera"};

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

// keys of earlier versions of the format and the keys that replaced them
constexpr std::pair<const char*, const char*> kRenamedKeys[] = {
    {"angle_deg", "angle"},                                // goals
    {"tolerance_deg", "tolerance"}, {"min_deg", "above"},  // rotation expectations
    {"max_deg", "below"},           {"value", "held"},     // held expectations
};

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

// the loader: one per LoadLevel/ParseLevel call
class Loader {
 public:
  Result<Level> Load(const std::string& path, std::optional<std::string_view> text) {
    Level level;
    level.path = path;
    toml::table root;
    std::vector<std::string> chain;
    if (Status s = ReadTree(path, text, SourceLoc{path, 0, 0}, chain, root)) return *s;
    level.files = m_files;
    if (Status s = Build(root, level)) return *s;
    return level;
  }

 private:
  // ---- step 1: read files, merge includes ----

  Status ReadTree(const std::string& path, std::optional<std::string_view> text,
                  const SourceLoc& from, std::vector<std::string>& chain, toml::table& out) {
    // an include that leads back to a file on the chain would never end
    std::error_code ec;
    const std::string canonical = fs::weakly_canonical(fs::path(path), ec).string();
    const std::string id = ec ? path : canonical;
    for (size_t i = 0; i < chain.size(); ++i) {
      if (m_chainIds[i] != id) continue;
      std::string cycle;
      for (size_t j = i; j < chain.size(); ++j) cycle += chain[j] + " -> ";
      return MakeError(from, "include cycle: " + cycle + path);
    }

    // the text: given, or read from the file
    std::string owned;
    if (!text) {
      std::ifstream in(path, std::ios::binary);
      if (!in) {
        return MakeError(from, from.line > 0 ? "cannot open included file '" + path + "'"
                                             : "cannot open level file");
      }
      std::stringstream buffer;
      buffer << in.rdbuf();
      owned = buffer.str();
      text = owned;
    }

    // syntax errors carry the parser's location
    toml::table table;
    try {
      table = toml::parse(*text, std::string(path));
    } catch (const toml::parse_error& e) {
      SourceLoc loc = Loc(e.source());
      loc.file = path;
      return MakeError(loc, std::string(e.description()));
    }

    // the included file's tree is the base this file's keys override
    if (const toml::node* include = table.get("include")) {
      const auto* name = include->as_string();
      if (!name) {
        return MakeError(Loc(include->source()),
                         "include must be a string (a path relative to this file), got " +
                             TomlTypeName(*include));
      }
      const std::string includePath =
          (fs::path(path).parent_path() / fs::path(name->get())).lexically_normal().string();
      chain.push_back(path);
      m_chainIds.push_back(id);
      toml::table base;
      const Status s = ReadTree(includePath, std::nullopt, Loc(include->source()), chain, base);
      chain.pop_back();
      m_chainIds.pop_back();
      if (s) return s;
      table.erase("include");
      Merge(base, table, 0);
      out = std::move(base);
    } else {
      out = std::move(table);
    }
    m_files.push_back(path);
    return std::nullopt;
  }

  // moves over's keys into base: tables merge key by key, the level's arrays of tables append,
  // anything else replaces; depth 0 is the root, depth 1 a table directly under it
  static void Merge(toml::table& base, toml::table& over, int depth, bool inScript = false) {
    for (auto&& [key, node] : over) {
      toml::node* existing = base.get(key);
      const bool appends = (depth == 0 && IsTopArray(key.str())) || (inScript && key == "contacts");
      if (existing && appends && existing->is_array() && node.is_array()) {
        for (toml::node& item : *node.as_array()) existing->as_array()->push_back(std::move(item));
      } else if (existing && !appends && existing->is_table() && node.is_table()) {
        Merge(*existing->as_table(), *node.as_table(), depth + 1, depth == 0 && key == "script");
      } else {
        base.insert_or_assign(key, std::move(node));
      }
    }
  }

  // ---- errors ----

  // the rank of a location: included files before the files that include them, then line, col
  std::tuple<int, int, int> Rank(const SourceLoc& loc) const {
    const auto it = std::find(m_files.begin(), m_files.end(), loc.file);
    return {static_cast<int>(it - m_files.begin()), loc.line, loc.col};
  }

  // the earliest error at a key or value; only when there is none, the earliest missing key, so
  // a mistake the user wrote is reported before one they left out
  Status Earliest(const Errors& errors, const Errors& missing = {}) const {
    const Errors& first = errors.empty() ? missing : errors;
    if (first.empty()) return std::nullopt;
    return *std::min_element(first.begin(), first.end(), [this](const Error& a, const Error& b) {
      return Rank(a.loc) < Rank(b.loc);
    });
  }

  static void UnknownKeys(const toml::table& t, const std::vector<std::string>& known,
                          const std::string& where, Errors& errors) {
    for (auto&& [k, v] : t) {
      if (std::find(known.begin(), known.end(), k.str()) != known.end()) continue;
      errors.push_back(MakeError(Loc(k.source()), "unknown key '" + std::string(k.str()) + "'" +
                                                      where + Hint(k.str(), known)));
    }
  }

  static void Missing(const toml::table& t, const char* key, const std::string& what,
                      Errors& errors) {
    if (t.contains(key)) return;
    errors.push_back(
        MakeError(Loc(t.source()), what + " is missing required key '" + std::string(key) + "'"));
  }

  static SourceLoc KeyLoc(const toml::table& t, std::string_view key) {
    for (auto&& [k, v] : t) {
      if (k == key) return Loc(k.source());
    }
    return Loc(t.source());
  }

  static SourceLoc ValueLoc(const toml::table& t, std::string_view key) {
    const toml::node* n = t.get(key);
    return n ? Loc(n->source()) : Loc(t.source());
  }

  // the tables of an array of tables, or an error naming the expected form
  static Status TablesOf(const toml::node& n, const std::string& key,
                         std::vector<const toml::table*>& tables) {
    const toml::array* a = n.as_array();
    if (!a) {
      return MakeError(Loc(n.source()),
                       key + " must be an array of tables [[" + key + "]], got " + TomlTypeName(n));
    }
    for (const toml::node& item : *a) {
      if (!item.is_table()) {
        return MakeError(Loc(item.source()), key + " must hold tables, got " + TomlTypeName(item));
      }
      tables.push_back(item.as_table());
    }
    return std::nullopt;
  }

  // ---- steps 2 and 3: validate and build ----

  Status Build(const toml::table& root, Level& level) {
    // the top level: only known keys, name and description are strings
    {
      Errors errors;
      const std::vector<std::string> known(std::begin(kTopKeys), std::end(kTopKeys));
      UnknownKeys(root, known, "", errors);
      for (const char* key : {"name", "description"}) {
        const toml::node* n = root.get(key);
        if (n && !n->is_string()) {
          errors.push_back(MakeError(
              Loc(n->source()), std::string(key) + " must be a string, got " + TomlTypeName(*n)));
        }
      }
      for (const char* key : kParamTables) {
        const toml::node* n = root.get(key);
        if (n && !n->is_table()) {
          errors.push_back(MakeError(Loc(n->source()), std::string(key) + " must be a table [" +
                                                           key + "], got " + TomlTypeName(*n)));
        }
      }
      if (const toml::node* n = root.get("script"); n && !n->is_table()) {
        errors.push_back(MakeError(Loc(n->source()),
                                   "script must be a table [script], got " + TomlTypeName(*n)));
      }
      if (Status s = Earliest(errors)) return s;
    }
    level.name = root["name"].value_or(fs::path(level.path).stem().string());
    level.description = root["description"].value_or(std::string());

    if (Status s = ReadParams(root, "", level.params)) return s;
    if (Status s = BuildObjects(root, level)) return s;
    if (Status s = BuildScript(root, level)) return s;
    if (Status s = BuildVariants(root, level)) return s;
    if (Status s = BuildExpectations(root, level)) return s;
    if (Status s = BuildGoals(root, level)) return s;
    return std::nullopt;
  }

  // the parameter tables of `root` (the level, or a variant) applied to params
  Status ReadParams(const toml::table& root, const std::string& prefix, LevelParams& params) {
    Errors errors;
    for (const ParamSection& section : Sections(params)) {
      const toml::table* t = root[section.name].as_table();
      if (!t) continue;
      TableReader reader(*t, prefix + section.name + ".");
      section.describe(reader);
      errors.insert(errors.end(), reader.errors.begin(), reader.errors.end());
      UnknownKeys(*t, reader.known, " in [" + prefix + section.name + "]", errors);
    }
    return Earliest(errors);
  }

  Status BuildObjects(const toml::table& root, Level& level) {
    const toml::node* node = root.get("objects");
    if (!node) return std::nullopt;
    std::vector<const toml::table*> tables;
    if (Status s = TablesOf(*node, "objects", tables)) return s;
    for (const toml::table* t : tables) {
      ObjectSpec o;
      o.loc = Loc(t->source());
      if (Status s = ReadObject(*t, level, o)) return s;
      level.objects.push_back(std::move(o));
    }
    return std::nullopt;
  }

  Status ReadObject(const toml::table& t, const Level& level, ObjectSpec& o) {
    // types and ranges of every key, then keys that do not fit the shape
    TableReader reader(t, "");
    DescribeObject(o, reader);
    Errors errors = reader.errors;
    UnknownKeys(t, reader.known, " in an object", errors);
    Errors missing;
    Missing(t, "name", "object", missing);
    Missing(t, "shape", "object", missing);
    Missing(t, "pos", "object", missing);
    const std::string shapeName = kObjectShapeNames[static_cast<int>(o.shape)];
    if (t.contains("shape") && !reader.bad.count("shape")) {
      std::string fits;
      for (const char* key : {"size_x", "size_y", "radius", "top_radius", "height", "points"}) {
        if (ObjectKeyApplies(o.shape, key)) fits += (fits.empty() ? "" : ", ") + std::string(key);
      }
      for (auto&& [k, v] : t) {
        if (ObjectKeyApplies(o.shape, k.str())) continue;
        errors.push_back(MakeError(Loc(k.source()), "'" + std::string(k.str()) +
                                                        "' does not apply to a " + shapeName +
                                                        " (its size keys: " + fits + ")"));
      }
      if (ObjectKeyApplies(o.shape, "points") && !t.contains("points")) {
        missing.push_back(
            MakeError(Loc(t.source()), "a " + shapeName + " object needs 'points', its outline"));
      }
    }
    if (Status s = Earliest(errors, missing)) return s;

    // meaning: a unique name, a valid outline, consistent friction and mass, on the table
    if (o.name.empty()) return MakeError(ValueLoc(t, "name"), "name must not be empty");
    if (const ObjectSpec* first = level.FindObject(o.name)) {
      return MakeError(ValueLoc(t, "name"), "duplicate object name '" + o.name +
                                                "' (first defined at " + first->loc.Format() + ")");
    }
    if (t.contains("mass") && t.contains("density")) {
      return MakeError(KeyLoc(t, "density"), "give either mass or density, not both");
    }
    // the physics module's own checks of the shape, mass and friction, at the key they are about
    std::string field;
    if (Status s = ValidateObject(o, level.params.physics, &field)) {
      const bool atKey = t.contains(field);
      return MakeError(atKey ? ValueLoc(t, field) : Loc(t.source()), s->message);
    }
    // the whole footprint, not just the centre, must be on the table
    const TableParams& table = level.params.table;
    const auto [low, high] = FootprintBounds(o);
    if (low.x() < 0 || low.y() < 0 || high.x() > table.width || high.y() > table.height) {
      return MakeError(ValueLoc(t, "pos"),
                       "object '" + o.name + "' reaches off the table: its footprint spans " +
                           Span(low.x(), high.x()) + " x " + Span(low.y(), high.y()) +
                           " cm, the table [0, " + FormatDouble(table.width) + "] x [0, " +
                           FormatDouble(table.height) + "] cm");
    }
    return std::nullopt;
  }

  Status BuildScript(const toml::table& root, Level& level) {
    Script& script = level.script;
    const toml::table* t = root["script"].as_table();
    std::optional<double> duration;
    if (t) {
      script.loc = Loc(t->source());
      // duration and interpolation
      Errors errors;
      UnknownKeys(*t, {"duration", "interpolation", "contacts", "recording"}, " in [script]",
                  errors);
      struct Head {
        double duration = 1.0;
        Interpolation interpolation = Interpolation::kLinear;
      } head;
      TableReader reader(*t, "script.");
      reader.Real("duration", head.duration, 0.01, 3600, "s", "");
      VisitEnum(reader, "interpolation", head.interpolation, kInterpolationNames, "");
      reader.Text("recording", script.recording, "");
      errors.insert(errors.end(), reader.errors.begin(), reader.errors.end());
      if (Status s = Earliest(errors)) return s;
      if (t->contains("duration")) duration = head.duration;
      script.interpolation = head.interpolation;
      if (Status s = ReadRecording(*t, level)) return s;

      // contacts
      if (const toml::node* contacts = t->get("contacts")) {
        std::vector<const toml::table*> tables;
        if (Status s = TablesOf(*contacts, "script.contacts", tables)) return s;
        for (const toml::table* c : tables) {
          ScriptContact contact;
          contact.loc = Loc(c->source());
          contact.interpolation = script.interpolation;
          if (Status s = ReadContact(*c, script, contact)) return s;
          script.contacts.push_back(std::move(contact));
        }
      }
    }

    // the duration covers every keyframe; by default it runs on to let objects settle, or as long
    // as the recording
    const double last = LastKeyframeTime(script);
    if (!duration && !script.recording.empty()) {
      script.duration =
          static_cast<double>(script.recordingFrames) / level.params.physics.frameRate;
    } else if (!duration) {
      script.duration = last + kScriptSettleTime;
    } else if (*duration < last) {
      return MakeError(ValueLoc(*t, "duration"), "duration " + FormatDouble(*duration) +
                                                     " s ends before the last keyframe at " +
                                                     FormatDouble(last) + " s");
    } else {
      script.duration = *duration;
    }
    return std::nullopt;
  }

  // [script] recording: a video file, relative to the level file that names it, that exists and
  // holds frames; it replaces the contacts
  static Status ReadRecording(const toml::table& t, Level& level) {
    Script& script = level.script;
    if (script.recording.empty()) {
      if (t.contains("recording")) return MakeError(ValueLoc(t, "recording"), "recording is empty");
      return std::nullopt;
    }
    const SourceLoc at = ValueLoc(t, "recording");
    if (t.contains("contacts")) {
      return MakeError(at, "a recording replaces the script's contacts: give one or the other");
    }
    const fs::path name(script.recording);
    const std::string path =
        name.is_absolute() ? name.string()
                           : (fs::path(at.file).parent_path() / name).lexically_normal().string();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
      return MakeError(at,
                       "recording '" + script.recording + "' not found (looked for " + path + ")");
    }
    // count the frames: the default duration, and a check that the file is a readable video
    Result<int64_t> counted = CountRecordingFrames(path);
    if (!counted.ok()) {
      return MakeError(
          at, "recording '" + script.recording + "' cannot be read as a video (" + path + ")");
    }
    const int64_t frames = counted.value();
    if (frames == 0) return MakeError(at, "recording '" + script.recording + "' holds no frames");
    script.recording = path;
    script.recordingFrames = frames;
    return std::nullopt;
  }

  Status ReadContact(const toml::table& t, const Script& script, ScriptContact& contact) {
    // name, interpolation and the shape's keys
    TableReader reader(t, "");
    reader.Text("name", contact.name, "");
    VisitEnum(reader, "interpolation", contact.interpolation, kInterpolationNames, "");
    DescribeContactShape(contact.shape, reader);
    reader.known.emplace_back("keys");
    Errors errors = reader.errors;
    UnknownKeys(t, reader.known, " in a contact", errors);
    Errors missing;
    Missing(t, "name", "contact", missing);
    Missing(t, "shape", "contact", missing);
    Missing(t, "keys", "contact", missing);
    const std::string shapeName = kShapeKindNames[static_cast<int>(contact.shape.kind)];
    if (t.contains("shape") && !reader.bad.count("shape")) {
      std::string fits;
      for (const char* key : {"radius", "radius_x", "radius_y", "length", "scale", "points"}) {
        if (ContactKeyApplies(contact.shape.kind, key)) {
          fits += (fits.empty() ? "" : ", ") + std::string(key);
        }
      }
      for (auto&& [k, v] : t) {
        if (ContactKeyApplies(contact.shape.kind, k.str())) continue;
        errors.push_back(MakeError(Loc(k.source()), "'" + std::string(k.str()) +
                                                        "' does not apply to a " + shapeName +
                                                        " contact (its size keys: " + fits + ")"));
      }
      if (ContactKeyApplies(contact.shape.kind, "points") && !t.contains("points")) {
        missing.push_back(
            MakeError(Loc(t.source()), "a " + shapeName + " contact needs 'points', its outline"));
      }
    }
    if (Status s = Earliest(errors, missing)) return s;

    // a unique name and a valid outline
    if (contact.name.empty()) return MakeError(ValueLoc(t, "name"), "name must not be empty");
    for (const ScriptContact& other : script.contacts) {
      if (other.name == contact.name) {
        return MakeError(ValueLoc(t, "name"), "duplicate contact name '" + contact.name +
                                                  "' (first defined at " + other.loc.Format() +
                                                  ")");
      }
    }
    if (ContactKeyApplies(contact.shape.kind, "points")) {
      const bool convex = contact.shape.kind == ShapeKind::kConvexPolygon;
      if (auto problem = PolygonProblem(contact.shape.points, convex)) {
        return MakeError(ValueLoc(t, "points"),
                         "points of a " + shapeName + " contact " + *problem);
      }
    }

    // keyframes, strictly increasing in time
    const toml::node& keysNode = *t.get("keys");
    const toml::array* keys = keysNode.as_array();
    if (!keys || keys->empty()) {
      return MakeError(Loc(keysNode.source()),
                       "keys must be a non-empty array of keyframes [{t = 0, pos = [x, y]}, ...]");
    }
    for (const toml::node& item : *keys) {
      const toml::table* k = item.as_table();
      if (!k) {
        return MakeError(Loc(item.source()),
                         "a keyframe must be a table {t = ..., pos = [x, y], angle = ...}, got " +
                             TomlTypeName(item));
      }
      Keyframe key;
      key.loc = Loc(k->source());
      TableReader keyReader(*k, "");
      keyReader.Real("t", key.t, 0, 3600, "s", "");
      keyReader.Vector("pos", key.pose.pos, -1000, 1000, "cm", "");
      keyReader.Angle("angle", key.pose.angle, -36000, 36000, "deg", "");
      Errors keyErrors = keyReader.errors;
      Errors keyMissing;
      UnknownKeys(*k, keyReader.known, " in a keyframe", keyErrors);
      Missing(*k, "t", "keyframe", keyMissing);
      Missing(*k, "pos", "keyframe", keyMissing);
      if (Status s = Earliest(keyErrors, keyMissing)) return s;
      if (!contact.keys.empty() && key.t <= contact.keys.back().t) {
        return MakeError(key.loc, "keyframe out of order: t = " + FormatDouble(key.t) +
                                      " s is not after the previous keyframe's t = " +
                                      FormatDouble(contact.keys.back().t) + " s");
      }
      contact.keys.push_back(key);
    }
    return std::nullopt;
  }

  Status BuildVariants(const toml::table& root, Level& level) {
    const toml::node* node = root.get("variants");
    if (!node) return std::nullopt;
    std::vector<const toml::table*> tables;
    if (Status s = TablesOf(*node, "variants", tables)) return s;
    for (const toml::table* t : tables) {
      Variant variant;
      variant.loc = Loc(t->source());
      variant.params = level.params;
      Errors errors;
      std::vector<std::string> known(std::begin(kParamTables), std::end(kParamTables));
      known.emplace_back("name");
      UnknownKeys(*t, known, " in a variant", errors);
      Errors missing;
      Missing(*t, "name", "variant", missing);
      TableReader reader(*t, "");
      reader.Text("name", variant.name, "");
      errors.insert(errors.end(), reader.errors.begin(), reader.errors.end());
      for (const char* key : kParamTables) {
        const toml::node* n = t->get(key);
        if (n && !n->is_table()) {
          errors.push_back(MakeError(
              Loc(n->source()), std::string(key) + " must be a table, got " + TomlTypeName(*n)));
        }
      }
      if (Status s = Earliest(errors, missing)) return s;
      if (variant.name.empty()) return MakeError(ValueLoc(*t, "name"), "name must not be empty");
      if (const Variant* first = level.FindVariant(variant.name)) {
        return MakeError(ValueLoc(*t, "name"), "duplicate variant name '" + variant.name +
                                                   "' (first defined at " + first->loc.Format() +
                                                   ")");
      }
      if (Status s = ReadParams(*t, "variants.", variant.params)) return s;
      level.variants.push_back(std::move(variant));
    }
    return std::nullopt;
  }

  // reads an optional region: min + max, or center + radius
  static Status ReadRegion(const toml::table& t, bool required, const std::string& what,
                           std::optional<Region>& region) {
    const bool rect = t.contains("min") || t.contains("max");
    const bool circle = t.contains("center") || t.contains("radius");
    if (rect && circle) {
      return MakeError(KeyLoc(t, t.contains("center") ? "center" : "radius"),
                       "give a region as min and max, or as center and radius, not both");
    }
    if (!rect && !circle) {
      if (!required) return std::nullopt;
      return MakeError(Loc(t.source()),
                       what + " needs a region: min and max, or center and radius");
    }
    Region r;
    TableReader reader(t, "");
    Errors errors;
    Errors missing;
    if (rect) {
      r.kind = Region::Kind::kRect;
      reader.Vector("min", r.min, -1000, 1000, "cm", "");
      reader.Vector("max", r.max, -1000, 1000, "cm", "");
      errors = reader.errors;
      Missing(t, "min", what, missing);
      Missing(t, "max", what, missing);
    } else {
      r.kind = Region::Kind::kCircle;
      reader.Vector("center", r.center, -1000, 1000, "cm", "");
      reader.Real("radius", r.radius, 0.001, 1000, "cm", "");
      errors = reader.errors;
      Missing(t, "center", what, missing);
      Missing(t, "radius", what, missing);
    }
    if (!errors.empty()) {
      // the earliest in the file
      return *std::min_element(errors.begin(), errors.end(), [](const Error& a, const Error& b) {
        return std::tie(a.loc.line, a.loc.col) < std::tie(b.loc.line, b.loc.col);
      });
    }
    if (!missing.empty()) return missing.front();
    if (rect && !(r.min.x() < r.max.x() && r.min.y() < r.max.y())) {
      return MakeError(ValueLoc(t, "max"), "max " + VecText(r.max) + " must be above min " +
                                               VecText(r.min) + " in both x and y");
    }
    region = r;
    return std::nullopt;
  }

  Status CheckObjectName(const toml::table& t, const char* key, const std::string& name,
                         const Level& level, bool allowTable) {
    if (allowTable && name == "table") return std::nullopt;
    if (level.FindObject(name)) return std::nullopt;
    std::vector<std::string> names;
    for (const ObjectSpec& o : level.objects) names.push_back(o.name);
    if (allowTable) names.emplace_back("table");
    return MakeError(ValueLoc(t, key), "unknown object '" + name + "'" + DidYouMean(name, names));
  }

  Status BuildExpectations(const toml::table& root, Level& level) {
    const toml::node* node = root.get("expect");
    if (!node) return std::nullopt;
    std::vector<const toml::table*> tables;
    if (Status s = TablesOf(*node, "expect", tables)) return s;
    for (const toml::table* t : tables) {
      Expectation e;
      if (Status s = ReadExpectation(*t, level, e)) return s;
      level.expectations.push_back(std::move(e));
    }
    return std::nullopt;
  }

  Status ReadExpectation(const toml::table& t, const Level& level, Expectation& e) {
    e.loc = Loc(t.source());
    // the kind decides which keys belong
    const toml::node* kindNode = t.get("kind");
    if (!kindNode) return MakeError(e.loc, "expectation is missing required key 'kind'");
    {
      TableReader reader(t, "");
      VisitEnum(reader, "kind", e.kind, kExpectKindNames, "");
      if (!reader.errors.empty()) return reader.errors.front();
    }
    std::vector<std::string> known = {"kind", "at", "mode", "variant", "label"};
    std::vector<std::string> required;
    switch (e.kind) {
      case ExpectKind::kPosition:
        known.insert(known.end(), {"object", "min", "max", "center", "radius"});
        required = {"object"};
        break;
      case ExpectKind::kRotation:
        known.insert(known.end(), {"object", "above", "below"});
        required = {"object"};
        break;
      case ExpectKind::kDisplacement:
        known.insert(known.end(), {"object", "above", "below"});
        required = {"object"};
        break;
      case ExpectKind::kHeld:
        known.insert(known.end(), {"object", "held"});
        required = {"object"};
        break;
      case ExpectKind::kResting:
        known.insert(known.end(), {"contact", "on", "fraction"});
        required = {"contact", "on"};
        break;
    }
    const std::string kindName = kExpectKindNames[static_cast<int>(e.kind)];
    const std::string what = "a " + kindName + " expectation";

    // types and ranges
    double at = 0.0;
    ProxyMode mode = ProxyMode::kPersistent;
    double aboveDeg = 0.0, belowDeg = 0.0;
    TableReader reader(t, "");
    reader.Real("at", at, 0, 3600, "s", "");
    VisitEnum(reader, "mode", mode, kProxyModeNames, "");
    reader.Text("variant", e.variant, "");
    reader.Text("label", e.label, "");
    reader.Text("object", e.object, "");
    reader.Text("contact", e.contact, "");
    reader.Text("on", e.on, "");
    if (e.kind == ExpectKind::kRotation) {
      reader.Real("above", aboveDeg, -36000, 36000, "deg", "");
      reader.Real("below", belowDeg, -36000, 36000, "deg", "");
    } else {
      reader.Real("above", e.above, 0, 10000, "cm", "");
      reader.Real("below", e.below, 0, 10000, "cm", "");
    }
    reader.Boolean("held", e.held, "");
    reader.Real("fraction", e.fraction, 0.01, 1, "", "");
    Errors errors = reader.errors;
    UnknownKeys(t, known, " in " + what, errors);
    Errors missing;
    for (const std::string& key : required) Missing(t, key.c_str(), what, missing);
    if (Status s = Earliest(errors, missing)) return s;
    if (t.contains("at")) e.at = at;
    if (t.contains("mode")) e.mode = mode;
    if (e.kind == ExpectKind::kRotation && t.contains("above")) e.minAngle = DegToRad(aboveDeg);
    if (e.kind == ExpectKind::kRotation && t.contains("below")) e.maxAngle = DegToRad(belowDeg);

    // kind-specific meaning
    switch (e.kind) {
      case ExpectKind::kPosition: {
        std::optional<Region> region;
        if (Status s = ReadRegion(t, true, what, region)) return s;
        e.region = *region;
        break;
      }
      case ExpectKind::kRotation:
        if (!t.contains("above") && !t.contains("below")) {
          return MakeError(e.loc, what + " needs above, below or both");
        }
        if (t.contains("above") && t.contains("below") && aboveDeg > belowDeg) {
          return MakeError(ValueLoc(t, "below"), "below (" + FormatDouble(belowDeg) +
                                                     " deg) must not be less than above (" +
                                                     FormatDouble(aboveDeg) + " deg)");
        }
        break;
      case ExpectKind::kDisplacement:
        if (!t.contains("above") && !t.contains("below")) {
          return MakeError(e.loc, what + " needs above, below or both");
        }
        if (t.contains("above") && t.contains("below") && e.above >= e.below) {
          return MakeError(ValueLoc(t, "below"), "below (" + FormatDouble(e.below) +
                                                     " cm) must be greater than above (" +
                                                     FormatDouble(e.above) + " cm)");
        }
        break;
      case ExpectKind::kHeld:
        break;
      case ExpectKind::kResting:
        break;
    }

    // names refer to things the level defines
    if (!e.object.empty()) {
      if (Status s = CheckObjectName(t, "object", e.object, level, false)) return s;
    }
    if (e.kind == ExpectKind::kResting) {
      if (Status s = CheckObjectName(t, "on", e.on, level, true)) return s;
      const ScriptContact* contact = nullptr;
      std::vector<std::string> names;
      for (const ScriptContact& c : level.script.contacts) {
        names.push_back(c.name);
        if (c.name == e.contact) contact = &c;
      }
      if (!contact) {
        return MakeError(ValueLoc(t, "contact"),
                         "unknown contact '" + e.contact + "'" + DidYouMean(e.contact, names));
      }
      // particles exist only while the contact does: by default at its last keyframe
      if (!e.at) {
        e.at = contact->End();
      } else if (*e.at < contact->Start() || *e.at > contact->End()) {
        return MakeError(ValueLoc(t, "at"),
                         "at = " + FormatDouble(*e.at) + " s is outside contact '" + contact->name +
                             "', which exists from " + FormatDouble(contact->Start()) + " s to " +
                             FormatDouble(contact->End()) + " s");
      }
    }
    if (!e.variant.empty() && !level.FindVariant(e.variant)) {
      std::vector<std::string> names;
      for (const Variant& v : level.variants) names.push_back(v.name);
      return MakeError(ValueLoc(t, "variant"),
                       "unknown variant '" + e.variant + "'" + DidYouMean(e.variant, names));
    }
    if (e.at && *e.at > level.script.duration) {
      return MakeError(ValueLoc(t, "at"), "at = " + FormatDouble(*e.at) +
                                              " s is after the end of the level at " +
                                              FormatDouble(level.script.duration) + " s");
    }
    return std::nullopt;
  }

  Status BuildGoals(const toml::table& root, Level& level) {
    const toml::node* node = root.get("goals");
    if (!node) return std::nullopt;
    std::vector<const toml::table*> tables;
    if (Status s = TablesOf(*node, "goals", tables)) return s;
    for (const toml::table* t : tables) {
      Goal g;
      g.loc = Loc(t->source());
      double angleDeg = 0.0;
      double toleranceDeg = RadToDeg(g.tolerance);
      TableReader reader(*t, "");
      reader.Text("object", g.object, "");
      reader.Text("label", g.label, "");
      reader.Real("angle", angleDeg, -360, 360, "deg", "");
      reader.Real("tolerance", toleranceDeg, 0, 180, "deg", "");
      reader.known.insert(reader.known.end(), {"min", "max", "center", "radius"});
      Errors errors = reader.errors;
      UnknownKeys(*t, reader.known, " in a goal", errors);
      Errors missing;
      Missing(*t, "object", "goal", missing);
      if (Status s = Earliest(errors, missing)) return s;
      if (Status s = ReadRegion(*t, false, "a goal", g.zone)) return s;
      if (t->contains("angle")) g.angle = DegToRad(angleDeg);
      if (t->contains("tolerance") && !g.angle) {
        return MakeError(KeyLoc(*t, "tolerance"), "tolerance needs angle");
      }
      g.tolerance = DegToRad(toleranceDeg);
      if (!g.zone && !g.angle) {
        return MakeError(g.loc,
                         "a goal needs a zone (min and max, or center and radius), angle or both");
      }
      if (Status s = CheckObjectName(*t, "object", g.object, level, false)) return s;
      level.goals.push_back(std::move(g));
    }
    return std::nullopt;
  }

  std::vector<std::string> m_files;     // files read, each after the files it includes
  std::vector<std::string> m_chainIds;  // canonical paths of the include chain
};

}  // namespace

Result<Level> LoadLevel(const std::string& path) {
  return Loader().Load(path, std::nullopt);
}

Result<Level> ParseLevel(std::string_view text, const std::string& path) {
  return Loader().Load(path, text);
}

}  // namespace pg
