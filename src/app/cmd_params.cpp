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

int RunParams(const std::string& only, bool markdown) {
  LevelParams defaults;
  bool found = only.empty();
  for (const ParamSection& section : Sections(defaults)) {
    if (!only.empty() && section.name != only) continue;
    found = true;
    if (markdown) {
      std::cout << "### [" << section.name << "]\n\n"
                << "| key | default | unit | range | meaning |\n"
                << "|---|---|---|---|---|\n";
    } else {
      std::cout << "[" << section.name << "]\n";
    }
    for (const FieldInfo& f : ListFields(section)) {
      if (markdown) {
        std::cout << "| `" << f.key << "` | `" << f.value << "` | " << f.unit << " | "
                  << RangeText(f) << " | " << f.doc << " |\n";
      } else {
        std::cout << f.key << " = " << f.value << "    # " << f.doc;
        if (!f.unit.empty() && f.unit != "1") std::cout << ", " << f.unit;
        std::cout << " (" << RangeText(f) << ")\n";
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
  cmd->add_option("--section", section, "Only this section (table, physics, proxies, ...)");
  cmd->add_flag("--markdown", markdown, "Print Markdown tables, as in docs/levels.md");
  cmd->callback([&exitCode] { exitCode = RunParams(section, markdown); });
}

}  // namespace pg
