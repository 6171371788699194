// Loader: [script], its contacts and keyframes, and a recording as input.
#include "describe.h"
#include "loader.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/recorder.h"
#include "proxygrasp/tuio/decoder.h"
#include "proxygrasp/tuio/touchlib_xml.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace pg::levelfile {

namespace fs = std::filesystem;

MaybeError Loader::BuildScript(const toml::table& root, Level& level) {
  Script& script = level.script;
  const toml::table* t = root["script"].as_table();
  std::optional<double> duration;
  if (t) {
    script.loc = Loc(t->source());
    // duration, interpolation and recording
    TableReader reader(*t, "script.");
    DescribeScript(script, reader);
    reader.known.emplace_back("contacts");
    Errors errors = reader.errors;
    UnknownKeys(*t, reader.known, " in [script]", errors);
    if (MaybeError s = Earliest(errors)) return s;
    if (t->contains("duration")) duration = script.duration;
    if (MaybeError s = ReadRecording(*t, level)) return s;
    if (MaybeError s = ReadTuio(*t, level)) return s;

    // contacts
    MaybeError s =
        EachTable(t->get("contacts"), "script.contacts", [&](const toml::table& c) -> MaybeError {
          ScriptContact contact;
          contact.loc = Loc(c.source());
          contact.interpolation = script.interpolation;
          if (MaybeError s = ReadContact(c, script, contact)) return s;
          script.contacts.push_back(std::move(contact));
          return std::nullopt;
        });
    if (s) return s;
  }

  // the duration covers every keyframe; by default it runs on to let objects settle, or as long
  // as the recording
  const double last = LastKeyframeTime(script);
  if (!duration && !script.recording.empty()) {
    script.duration = static_cast<double>(script.recordingFrames) / level.params.physics.frameRate;
  } else if (!duration && script.tuioBundles) {
    // the stream's last bundle, the timeout that lifts what is still down, then time to settle
    const std::vector<double> arrivals =
        ReplayArrivals(*script.tuioBundles, 1.0 / level.params.physics.frameRate);
    script.duration = arrivals.back() + TuioParams().timeout + kScriptSettleTime;
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

namespace {

// A file a level names (`what` says which, for the message): an absolute path, or one relative to
// the level file; an Error at the key when it is not a file.
Result<std::string> ResolveLevelFile(const SourceLoc& at, const std::string& name,
                                     const std::string& what) {
  const fs::path given(name);
  const std::string path =
      given.is_absolute() ? given.string()
                          : (fs::path(at.file).parent_path() / given).lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    return MakeError(at, what + " '" + name + "' not found (looked for " + path + ")");
  }
  return path;
}

}  // namespace

// [script] recording: a video file, relative to the level file that names it, that exists and
// holds frames; it replaces the contacts
MaybeError Loader::ReadRecording(const toml::table& t, Level& level) {
  Script& script = level.script;
  if (script.recording.empty()) {
    if (t.contains("recording")) return MakeError(ValueLoc(t, "recording"), "recording is empty");
    return std::nullopt;
  }
  const SourceLoc at = ValueLoc(t, "recording");
  if (t.contains("contacts")) {
    return MakeError(at, "a recording replaces the script's contacts: give one or the other");
  }
  Result<std::string> resolved = ResolveLevelFile(at, script.recording, "recording");
  if (!resolved.ok()) return resolved.error();
  const std::string path = resolved.value();
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

// [script] tuio: a recorded TUIO stream in touchlib XML, relative to the level file that names
// it, read whole here so that a broken file is an error at load; it replaces the contacts and a
// video recording
MaybeError Loader::ReadTuio(const toml::table& t, Level& level) {
  Script& script = level.script;
  if (script.tuio.empty()) {
    if (t.contains("tuio")) return MakeError(ValueLoc(t, "tuio"), "tuio is empty");
    return std::nullopt;
  }
  const SourceLoc at = ValueLoc(t, "tuio");
  if (t.contains("contacts"))
    return MakeError(at, "a TUIO stream replaces the script's contacts: give one or the other");
  if (!script.recording.empty())
    return MakeError(at, "a TUIO stream and a video recording are both inputs: give one");
  Result<std::string> resolved = ResolveLevelFile(at, script.tuio, "TUIO stream");
  if (!resolved.ok()) return resolved.error();
  const std::string path = resolved.value();
  Result<std::vector<OscBundle>> read = ReadTouchlibXml(path);
  if (!read.ok())
    return MakeError(at, "TUIO stream '" + script.tuio + "': " + read.error().Format());
  if (read.value().empty())
    return MakeError(at, "TUIO stream '" + script.tuio + "' holds no packets");
  script.tuio = path;
  script.tuioBundles = std::make_shared<const std::vector<OscBundle>>(std::move(read.value()));
  return std::nullopt;
}

MaybeError Loader::ReadContact(const toml::table& t, const Script& script, ScriptContact& contact) {
  // name, interpolation and the shape's keys
  Errors errors, missing;
  const auto describe = [&contact](TableReader& r) {
    DescribeScriptContact(contact, r);
    r.known.emplace_back("keys");
  };
  const std::set<std::string> bad =
      ReadKeys(t, describe, " in a contact", "contact", {"name", "shape", "keys"}, errors, missing);
  const std::string shapeName = kShapeKindNames[static_cast<int>(contact.shape.kind)];
  if (t.contains("shape") && !bad.count("shape")) {
    const ShapeKind kind = contact.shape.kind;
    CheckShapeKeys(
        t, [kind](std::string_view key) { return ContactKeyApplies(kind, key); },
        shapeName + " contact", shapeName + " contact", ContactSizeKeys(kind), errors, missing);
  }
  if (MaybeError s = Earliest(errors, missing)) return s;

  // a unique name and a valid outline
  if (contact.name.empty()) return MakeError(ValueLoc(t, "name"), "name must not be empty");
  for (const ScriptContact& other : script.contacts) {
    if (other.name == contact.name) {
      return MakeError(ValueLoc(t, "name"), "duplicate contact name '" + contact.name +
                                                "' (first defined at " + other.loc.Format() + ")");
    }
  }
  if (ContactKeyApplies(contact.shape.kind, "points")) {
    const bool convex = contact.shape.kind == ShapeKind::kConvexPolygon;
    if (auto problem = PolygonProblem(contact.shape.points, convex)) {
      return MakeError(ValueLoc(t, "points"), "points of a " + shapeName + " contact " + *problem);
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
    Errors keyErrors, keyMissing;
    ReadKeys(
        *k, [&key](TableReader& r) { DescribeKeyframe(key, r); }, " in a keyframe", "keyframe",
        {"t", "pos"}, keyErrors, keyMissing);
    if (MaybeError s = Earliest(keyErrors, keyMissing)) return s;
    if (!contact.keys.empty() && key.t <= contact.keys.back().t) {
      return MakeError(key.loc, "keyframe out of order: t = " + FormatDouble(key.t) +
                                    " s is not after the previous keyframe's t = " +
                                    FormatDouble(contact.keys.back().t) + " s");
    }
    contact.keys.push_back(key);
  }
  return std::nullopt;
}

}  // namespace pg::levelfile
