#pragma once

namespace lt {

inline constexpr double Pi = 3.14159265358979323846;
inline constexpr double TwoPi = 2.0 * Pi;
inline constexpr double InvPi = 1.0 / Pi;
inline constexpr double InvTwoPi = 1.0 / TwoPi;
inline constexpr double InvFourPi = 1.0 / (4.0 * Pi);

inline constexpr double degToRad(double d) { return d * (Pi / 180.0); }
inline constexpr double radToDeg(double r) { return r * (180.0 / Pi); }

} // namespace lt
