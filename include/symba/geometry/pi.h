// kPi, kTwoPi and kDegreesPerRadian: the constants alone, for headers that need no angle
// function (angle.h, which includes Ceres's Jet), e.g. option defaults.
#ifndef SYMBA_GEOMETRY_PI_H_
#define SYMBA_GEOMETRY_PI_H_

namespace symba {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;
inline constexpr double kDegreesPerRadian = 180.0 / kPi;

}  // namespace symba

#endif  // SYMBA_GEOMETRY_PI_H_
