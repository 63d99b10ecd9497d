// The noise a replay's backend used, as summary.json and objects.json
// write it (docs/replay.md): per class "noise" (the estimate, the weights,
// the samples, the hypotheses' scatter, the claims) and "motion" (what the
// camera's motion factors were weighed with).
#ifndef SYMBA_SRC_IO_NOISE_JSON_H_
#define SYMBA_SRC_IO_NOISE_JSON_H_

#include <vector>

#include "io/json_writer.h"
#include "symba/backend/estimates.h"

namespace symba::io_internal {

// The member "noise": an array, one object per class.
void WriteNoise(const std::vector<ClassNoiseEstimate>& noise, JsonWriter* json);
// The member "motion".
void WriteMotionNoise(const MotionNoiseReport& motion, JsonWriter* json);

}  // namespace symba::io_internal

#endif  // SYMBA_SRC_IO_NOISE_JSON_H_
