// What the keyframe graph's covariances took the noise of each group of its
// edges to be (docs/backend.md "Covariances"): the variance its information
// states times a factor the residuals of the estimate showed.
#ifndef SYMBA_BACKEND_COVARIANCE_NOISE_H_
#define SYMBA_BACKEND_COVARIANCE_NOISE_H_

#include <string>

namespace symba {

struct CovarianceNoiseGroup {
  // "motion S_T m S_R rad, ..." (the camera steps stated with those sigmas,
  // to a quarter octave) or "detections CLASS, ...".
  std::string name;
  int edges = 0;      // edges in the group
  int residuals = 0;  // of them, those whose residual was measured
  // The mean squared whitened residual per degree of freedom (translation,
  // rotation; where the noise is as stated its expected value is 1 minus
  // the edges' mean leverage; 0 for rotation rows that measure nothing)
  // and the correlation of consecutive residuals (0 to 0.98).
  double residual_t = 0.0;
  double residual_r = 0.0;
  double correlation_t = 0.0;
  double correlation_r = 0.0;
  // Something besides these edges held the estimate (map points a step's
  // two keyframes shared; an object's many views with a stated noise), so
  // its residuals are its errors and may show a noise below the stated;
  // else they only bound it from below.
  bool held_by_others = false;
  // The variance factors applied (1: as stated).
  double factor_t = 1.0;
  double factor_r = 1.0;
};

}  // namespace symba

#endif  // SYMBA_BACKEND_COVARIANCE_NOISE_H_
