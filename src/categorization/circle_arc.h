// Arcs on the circle of angles, as the categorization measures them.
#ifndef SYMBA_CATEGORIZATION_CIRCLE_ARC_H_
#define SYMBA_CATEGORIZATION_CIRCLE_ARC_H_

#include "symba/geometry/angle.h"

namespace symba {
namespace categorization {

// Counter-clockwise arc from angle `from` to angle `to` (any real angles),
// in [0, 2 pi): WrapToPi(to) - WrapToPi(from), plus 2 pi when negative.
inline double ForwardArc(double from, double to) {
  double d = WrapToPi(to) - WrapToPi(from);
  if (d < 0.0) d += kTwoPi;
  if (d >= kTwoPi) d -= kTwoPi;
  return d;
}

}  // namespace categorization
}  // namespace symba

#endif  // SYMBA_CATEGORIZATION_CIRCLE_ARC_H_
