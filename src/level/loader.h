// The level loader: reads a level's TOML files (includes merged into one tree whose nodes keep
// their file:line:col), checks every key against the code's descriptions and builds the Level.
// The first error in processing order is returned; within one table the earliest in the file
// wins. Its steps live in loader.cpp (files, includes, errors, parameters and variants),
// read_objects.cpp, read_script.cpp and read_checks.cpp (expectations and goals); the keys they
// read are described in describe.h. Private to the level module.
#pragma once

#include "toml_reader.h"

#include "proxygrasp/level/level.h"

#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

namespace pg::levelfile {

/// One loader per LoadLevel or ParseLevel call.
class Loader {
 public:
  Result<Level> Load(const std::string& path, std::optional<std::string_view> text);

 private:
  MaybeError ReadTree(const std::string& path, std::optional<std::string_view> text,
                      const SourceLoc& from, std::vector<std::string>& chain, toml::table& out);

  // moves over's keys into base: tables merge key by key, the level's arrays of tables append,
  // anything else replaces; depth 0 is the root, depth 1 a table directly under it
  static void Merge(toml::table& base, toml::table& over, int depth, bool inScript = false);

  // the rank of a location: included files before the files that include them, then line, col
  std::tuple<int, int, int> Rank(const SourceLoc& loc) const;

  // the earliest error at a key or value; only when there is none, the earliest missing key, so
  // a mistake the user wrote is reported before one they left out
  MaybeError Earliest(const Errors& errors, const Errors& missing = {}) const;

  static void UnknownKeys(const toml::table& t, const std::vector<std::string>& known,
                          const std::string& where, Errors& errors);

  static void Missing(const toml::table& t, const char* key, const std::string& what,
                      Errors& errors);

  static SourceLoc KeyLoc(const toml::table& t, std::string_view key);

  static SourceLoc ValueLoc(const toml::table& t, std::string_view key);

  // the tables of an array of tables, or an error naming the expected form
  static MaybeError TablesOf(const toml::node& n, const std::string& key,
                             std::vector<const toml::table*>& tables);

  // read(table) for each table of the array of tables `node` (none when it is null), named `key`
  // in messages; the first error stops it
  template <typename Read>
  static MaybeError EachTable(const toml::node* node, const std::string& key, Read read) {
    if (!node) return std::nullopt;
    std::vector<const toml::table*> tables;
    if (MaybeError s = TablesOf(*node, key, tables)) return s;
    for (const toml::table* t : tables) {
      if (MaybeError s = read(*t)) return s;
    }
    return std::nullopt;
  }

  // reads t's keys through describe(reader): a wrong type or range, or a key not described
  // ("unknown key 'k'<where>"), goes to errors; a required key t lacks ("<what> is missing
  // required key 'k'") to missing. Returns the keys whose value was rejected.
  template <typename Describe>
  static std::set<std::string> ReadKeys(const toml::table& t, Describe describe,
                                        const std::string& where, const std::string& what,
                                        std::initializer_list<const char*> required, Errors& errors,
                                        Errors& missing) {
    TableReader reader(t, "");
    describe(reader);
    errors.insert(errors.end(), reader.errors.begin(), reader.errors.end());
    UnknownKeys(t, reader.known, where, errors);
    for (const char* key : required) Missing(t, key, what, missing);
    return reader.bad;
  }

  MaybeError Build(const toml::table& root, Level& level);

  // the parameter tables of `root` (the level, or a variant) applied to params
  MaybeError ReadParams(const toml::table& root, const std::string& prefix, LevelParams& params);

  MaybeError BuildObjects(const toml::table& root, Level& level);

  MaybeError ReadObject(const toml::table& t, const Level& level, ObjectSpec& o);

  MaybeError BuildScript(const toml::table& root, Level& level);

  // [script] recording: a video file, relative to the level file that names it, that exists and
  // holds frames; it replaces the contacts
  static MaybeError ReadRecording(const toml::table& t, Level& level);
  static MaybeError ReadTuio(const toml::table& t, Level& level);

  MaybeError ReadContact(const toml::table& t, const Script& script, ScriptContact& contact);

  MaybeError BuildVariants(const toml::table& root, Level& level);

  // reads an optional region: min + max, or center + radius
  static MaybeError ReadRegion(const toml::table& t, bool required, const std::string& what,
                               std::optional<Region>& region);

  MaybeError CheckObjectName(const toml::table& t, const char* key, const std::string& name,
                             const Level& level, bool allowTable);

  MaybeError BuildExpectations(const toml::table& root, Level& level);

  MaybeError ReadExpectation(const toml::table& t, const Level& level, Expectation& e);

  MaybeError BuildGoals(const toml::table& root, Level& level);

  std::vector<std::string> m_files;  // files read, each after the files it includes

  std::vector<std::string> m_chainIds;  // canonical paths of the include chain
};

}  // namespace pg::levelfile
