// Angle helpers: degree/radian conversion and wrapping. Angles are counter-clockwise positive (REP-103).
#pragma once

#include <cmath>
#include <numbers>

namespace squint {

constexpr double kPi = std::numbers::pi;

constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }

// Wraps to (-pi, pi].
inline double WrapPi(double a) {
  a = std::remainder(a, 2.0 * kPi);
  if (a <= -kPi) a += 2.0 * kPi;
  return a;
}

// Wraps to (-180, 180].
inline double WrapDeg(double a) { return RadToDeg(WrapPi(DegToRad(a))); }

// Smallest signed difference a - b, wrapped to (-pi, pi].
inline double AngleDiff(double a, double b) { return WrapPi(a - b); }

}  // namespace squint
