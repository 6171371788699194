// Small levels the run module's tests share, written as TOML so that they go through the loader as
// a user's level does: boxes and circular fingertips moving in a straight line.
#pragma once

#include "proxygrasp/level/level.h"

#include <gtest/gtest.h>

#include <string>

namespace pg::test {

/// An [[objects]] box of size x size x height cm centred at (x, y), 1 g/cm^3 unless mass is given.
inline std::string BoxToml(const std::string& name, double x, double y, double size = 4,
                           double height = 2) {
  return "\n[[objects]]\nname = \"" + name +
         "\"\nshape = \"box\"\nsize_x = " + std::to_string(size) +
         "\nsize_y = " + std::to_string(size) + "\nheight = " + std::to_string(height) +
         "\npos = [" + std::to_string(x) + ", " + std::to_string(y) + "]\n";
}

/// A [[script.contacts]] fingertip of radius 0.8 cm moving from (x0, y0) at t0 to (x1, y1) at t1.
inline std::string FingerToml(const std::string& name, double x0, double y0, double t0, double x1,
                              double y1, double t1) {
  return "\n[[script.contacts]]\nname = \"" + name +
         "\"\nshape = \"circle\"\nradius = 0.8\nkeys = [{t = " + std::to_string(t0) + ", pos = [" +
         std::to_string(x0) + ", " + std::to_string(y0) + "]}, {t = " + std::to_string(t1) +
         ", pos = [" + std::to_string(x1) + ", " + std::to_string(y1) + "]}]\n";
}

/// The level in text, which the test expects to load.
inline Level ParseOrFail(const std::string& text, const std::string& name = "test.toml") {
  const Result<Level> level = ParseLevel(text, name);
  EXPECT_TRUE(level.ok()) << level.error().Format();
  return level.ok() ? level.value() : Level{};
}

}  // namespace pg::test
