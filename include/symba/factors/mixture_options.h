// MixtureOptions: the max-mixtures' optional null hypothesis
// (max_mixture.h explains it). A header of its own, without Ceres, so that
// option structs can hold it.
#ifndef SYMBA_FACTORS_MIXTURE_OPTIONS_H_
#define SYMBA_FACTORS_MIXTURE_OPTIONS_H_

#include <cmath>

namespace symba {

struct MixtureOptions {
  // Add the null-hypothesis component.
  bool use_null_hypothesis = false;
  // Its weight, relative to the hypotheses' weights normalised to sum 1.
  double null_weight = 1e-3;
  // Its standard deviations are the nearest component's times this (> 1).
  double null_sigma_scale = 10.0;

  bool IsValid() const {
    return !use_null_hypothesis ||
           (std::isfinite(null_weight) && null_weight > 0.0 &&
            std::isfinite(null_sigma_scale) && null_sigma_scale > 1.0);
  }
};

}  // namespace symba

#endif  // SYMBA_FACTORS_MIXTURE_OPTIONS_H_
