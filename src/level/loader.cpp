// Loader: files, includes, error order, parameter tables and variants.
#include "loader.h"

#include "describe.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pg::levelfile {

namespace fs = std::filesystem;

Result<Level> Loader::Load(const std::string& path, std::optional<std::string_view> text) {
  Level level;
  level.path = path;
  toml::table root;
  std::vector<std::string> chain;
  if (MaybeError s = ReadTree(path, text, SourceLoc{path, 0, 0}, chain, root)) return *s;
  level.files = m_files;
  if (MaybeError s = Build(root, level)) return *s;
  return level;
}

MaybeError Loader::ReadTree(const std::string& path, std::optional<std::string_view> text,
                            const SourceLoc& from, std::vector<std::string>& chain,
                            toml::table& out) {
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
      return MakeError(
          Loc(include->source()),
          "include must be a string (a path relative to this file), got " + TomlTypeName(*include));
    }
    const std::string includePath =
        (fs::path(path).parent_path() / fs::path(name->get())).lexically_normal().string();
    chain.push_back(path);
    m_chainIds.push_back(id);
    toml::table base;
    const MaybeError s = ReadTree(includePath, std::nullopt, Loc(include->source()), chain, base);
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
void Loader::Merge(toml::table& base, toml::table& over, int depth, bool inScript) {
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

// the rank of a location: included files before the files that include them, then line, col
std::tuple<int, int, int> Loader::Rank(const SourceLoc& loc) const {
  const auto it = std::find(m_files.begin(), m_files.end(), loc.file);
  return {static_cast<int>(it - m_files.begin()), loc.line, loc.col};
}

// the earliest error at a key or value; only when there is none, the earliest missing key, so
// a mistake the user wrote is reported before one they left out
MaybeError Loader::Earliest(const Errors& errors, const Errors& missing) const {
  const Errors& first = errors.empty() ? missing : errors;
  if (first.empty()) return std::nullopt;
  return *std::min_element(first.begin(), first.end(), [this](const Error& a, const Error& b) {
    return Rank(a.loc) < Rank(b.loc);
  });
}

void Loader::UnknownKeys(const toml::table& t, const std::vector<std::string>& known,
                         const std::string& where, Errors& errors) {
  for (auto&& [k, v] : t) {
    if (std::find(known.begin(), known.end(), k.str()) != known.end()) continue;
    errors.push_back(MakeError(Loc(k.source()), "unknown key '" + std::string(k.str()) + "'" +
                                                    where + Hint(k.str(), known)));
  }
}

void Loader::Missing(const toml::table& t, const char* key, const std::string& what,
                     Errors& errors) {
  if (t.contains(key)) return;
  errors.push_back(
      MakeError(Loc(t.source()), what + " is missing required key '" + std::string(key) + "'"));
}

SourceLoc Loader::KeyLoc(const toml::table& t, std::string_view key) {
  for (auto&& [k, v] : t) {
    if (k == key) return Loc(k.source());
  }
  return Loc(t.source());
}

SourceLoc Loader::ValueLoc(const toml::table& t, std::string_view key) {
  const toml::node* n = t.get(key);
  return n ? Loc(n->source()) : Loc(t.source());
}

// the tables of an array of tables, or an error naming the expected form
MaybeError Loader::TablesOf(const toml::node& n, const std::string& key,
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

MaybeError Loader::Build(const toml::table& root, Level& level) {
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
        errors.push_back(MakeError(Loc(n->source()), std::string(key) + " must be a table [" + key +
                                                         "], got " + TomlTypeName(*n)));
      }
    }
    if (const toml::node* n = root.get("script"); n && !n->is_table()) {
      errors.push_back(
          MakeError(Loc(n->source()), "script must be a table [script], got " + TomlTypeName(*n)));
    }
    if (MaybeError s = Earliest(errors)) return s;
  }
  level.name = root["name"].value_or(fs::path(level.path).stem().string());
  level.description = root["description"].value_or(std::string());

  if (MaybeError s = ReadParams(root, "", level.params)) return s;
  if (MaybeError s = BuildObjects(root, level)) return s;
  if (MaybeError s = BuildScript(root, level)) return s;
  if (MaybeError s = BuildVariants(root, level)) return s;
  if (MaybeError s = BuildExpectations(root, level)) return s;
  if (MaybeError s = BuildGoals(root, level)) return s;
  return std::nullopt;
}

// the parameter tables of `root` (the level, or a variant) applied to params
MaybeError Loader::ReadParams(const toml::table& root, const std::string& prefix,
                              LevelParams& params) {
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

MaybeError Loader::BuildVariants(const toml::table& root, Level& level) {
  return EachTable(root.get("variants"), "variants", [&](const toml::table& t) -> MaybeError {
    Variant variant;
    variant.loc = Loc(t.source());
    variant.params = level.params;
    Errors errors;
    std::vector<std::string> known(std::begin(kParamTables), std::end(kParamTables));
    known.emplace_back("name");
    UnknownKeys(t, known, " in a variant", errors);
    Errors missing;
    Missing(t, "name", "variant", missing);
    TableReader reader(t, "");
    DescribeVariant(variant, reader);
    errors.insert(errors.end(), reader.errors.begin(), reader.errors.end());
    for (const char* key : kParamTables) {
      const toml::node* n = t.get(key);
      if (n && !n->is_table()) {
        errors.push_back(MakeError(Loc(n->source()),
                                   std::string(key) + " must be a table, got " + TomlTypeName(*n)));
      }
    }
    if (MaybeError s = Earliest(errors, missing)) return s;
    if (variant.name.empty()) return MakeError(ValueLoc(t, "name"), "name must not be empty");
    if (const Variant* first = level.FindVariant(variant.name)) {
      return MakeError(ValueLoc(t, "name"), "duplicate variant name '" + variant.name +
                                                "' (first defined at " + first->loc.Format() + ")");
    }
    if (MaybeError s = ReadParams(t, "variants.", variant.params)) return s;
    level.variants.push_back(std::move(variant));
    return std::nullopt;
  });
}

}  // namespace pg::levelfile
