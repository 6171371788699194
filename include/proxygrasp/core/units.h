// Units of the table frame: centimetres, grams, dynes, seconds, radians.
// 1 dyn = 1 g cm / s^2. Angles are radians in code; level files and traces use degrees.
#pragma once

namespace pg {

/// Standard gravity, cm/s^2.
inline constexpr double kGravity = 981.0;

/// Pi, non-dimensional.
inline constexpr double kPi = 3.14159265358979323846;

/// Centimetres per inch.
inline constexpr double kCmPerInch = 2.54;

/// Degrees to radians.
inline constexpr double DegToRad(double degrees) {
  return degrees * (kPi / 180.0);
}

/// Radians to degrees.
inline constexpr double RadToDeg(double radians) {
  return radians * (180.0 / kPi);
}

}  // namespace pg
