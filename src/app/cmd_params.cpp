// `proxygrasp params`: every level parameter with its default, range, unit and meaning.
#include "commands.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/level/params.h"

#include <iostream>

namespace pg {

namespace {

std::string RangeText(const FieldInfo& f) {
  switch (f.type) {
    case FieldInfo::Type::kReal:
    case FieldInfo::Type::kInteger:
      return FormatDouble(f.min) + " .. " + FormatDouble(f.max);
    case FieldInfo::Type::kBoolean:
      return "true, false";
    case FieldInfo::Type::kChoice: {
      std::string s;
      for (size_t i = 0; i < f.choices.size(); ++i) s += (i ? ", " : "") + f.choices[i];
      return s;
    }
    case FieldInfo::Type::kText:
      return "text";
    case FieldInfo::Type::kVector:
    case FieldInfo::Type::kPoints:
      return "each coordinate " + FormatDouble(f.min) + " .. " + FormatDouble(f.max);
  }
  return "";
}

const char* ApplyText(Apply apply) {
  return apply == Apply::kRestart ? "restarts the run" : "applies live";
}

// for docs/app.md: per section, the keys a running simulation takes and those that restart it
int RunLiveness() {
  LevelParams defaults;
  std::cout << "| section | applies live (the run keeps its state) | restarts the run |\n"
            << "|---|---|---|\n";
  for (const ParamSection& section : Sections(defaults)) {
    std::string live, restart;
    for (const FieldInfo& f : ListFields(section)) {
      std::string& list = f.apply == Apply::kRestart ? restart : live;
      list += (list.empty() ? "`" : ", `") + f.key + "`";
    }
    std::cout << "| `[" << section.name << "]` | " << (live.empty() ? "none" : live) << " | "
              << (restart.empty() ? "none" : restart) << " |\n";
  }
  return kExitOk;
}

int RunParams(const std::string& only, bool markdown) {
  LevelParams defaults;
  bool found = only.empty();
  for (const ParamSection& section : Sections(defaults)) {
    if (!only.empty() && section.name != only) continue;
    found = true;
    if (markdown) {
      std::cout << "### [" << section.name << "]\n\n"
                << "| key | default | unit | range | a change | meaning |\n"
                << "|---|---|---|---|---|---|\n";
    } else {
      std::cout << "[" << section.name << "]\n";
    }
    for (const FieldInfo& f : ListFields(section)) {
      if (markdown) {
        std::cout << "| `" << f.key << "` | `" << f.value << "` | " << f.unit << " | "
                  << RangeText(f) << " | " << ApplyText(f.apply) << " | " << f.doc << " |\n";
      } else {
        std::cout << f.key << " = " << f.value << "    # " << f.doc;
        if (!f.unit.empty() && f.unit != "1") std::cout << ", " << f.unit;
        std::cout << " (" << RangeText(f) << ")";
        if (f.apply == Apply::kRestart) std::cout << " [restart]";
        std::cout << "\n";
      }
    }
    std::cout << "\n";
  }
  if (!found) {
    std::cerr << "proxygrasp params: unknown section '" << only << "'\n";
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace

void AddParamsCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand(
      "params", "List every level parameter with its default, unit, range and meaning");
  // CLI11 binds options by reference, so they live as long as the program
  static std::string section;
  static bool markdown = false;
  static bool liveness = false;
  cmd->add_option("--section", section, "Only this section (table, physics, proxies, ...)");
  cmd->add_flag("--markdown", markdown, "Print Markdown tables, as in docs/levels.md");
  cmd->add_flag("--liveness", liveness,
                "Print which parameters apply live and which restart the run, as in docs/app.md");
  cmd->callback(
      [&exitCode] { exitCode = liveness ? RunLiveness() : RunParams(section, markdown); });
}

}  // namespace pg
