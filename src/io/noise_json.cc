#include "io/noise_json.h"

#include <optional>
#include <string_view>

namespace symba::io_internal {
namespace {

void OptionalMember(std::string_view key,
                    const std::optional<double>& value,
                    JsonWriter* json) {
  json->Key(key);
  if (value) {
    json->Double(*value);
  } else {
    json->Null();
  }
}

void WriteSamples(std::string_view key,
                  const ClassNoiseEstimate::Samples& samples,
                  JsonWriter* json) {
  json->Key(key).BeginObject();
  json->Member("levels", samples.levels)
      .Member("increments", samples.increments);
  OptionalMember("sigma_level", samples.sigma_level, json);
  OptionalMember("sigma_increment", samples.sigma_increment, json);
  json->Member("correlation", samples.correlation)
      .Member("inflation", samples.inflation)
      .EndObject();
}

}  // namespace

void WriteNoise(const std::vector<ClassNoiseEstimate>& noise,
                JsonWriter* json) {
  json->Key("noise").BeginArray();
  for (const ClassNoiseEstimate& c : noise) {
    json->BeginObject().Member("class", c.class_name);
    OptionalMember("sigma_t", c.sigma_t, json);
    OptionalMember("sigma_r", c.sigma_r, json);
    json->Member("weight_sigma_t", c.weight_sigma_t)
        .Member("weight_sigma_r", c.weight_sigma_r);
    WriteSamples("translation", c.translation, json);
    WriteSamples("rotation", c.rotation, json);
    json->Key("hypothesis_scatter")
        .BeginObject()
        .Member("detections", c.scatter.detections);
    OptionalMember("sigma_t", c.scatter.sigma_t, json);
    OptionalMember("sigma_r", c.scatter.sigma_r, json);
    json->EndObject();
    json->Key("claims")
        .BeginObject()
        .Member("translation_samples", c.claims.translation_samples)
        .Member("rotation_samples", c.claims.rotation_samples);
    OptionalMember("scale_t", c.claims.scale_t, json);
    OptionalMember("scale_r", c.claims.scale_r, json);
    json->Member("factor_t", c.claims.factor_t)
        .Member("factor_r", c.claims.factor_r)
        .EndObject();
    OptionalMember("track_ratio", c.track_ratio, json);
    json->Key("weights")
        .BeginObject()
        .Member("declared", c.weights.declared)
        .Member("scatter", c.weights.scatter)
        .Member("unstated", c.weights.unstated);
    OptionalMember("sigma_t", c.weights.sigma_t, json);
    OptionalMember("sigma_r", c.weights.sigma_r, json);
    json->EndObject();
    json->EndObject();
  }
  json->EndArray();
}

void WriteMotionNoise(const MotionNoiseReport& motion, JsonWriter* json) {
  json->Key("motion")
      .BeginObject()
      .Key("odometry")
      .BeginObject()
      .Member("steps", motion.odometry_steps);
  OptionalMember("sigma_t", motion.odometry_sigma_t, json);
  OptionalMember("sigma_r", motion.odometry_sigma_r, json);
  json->EndObject()
      .Key("frontend_poses")
      .BeginObject()
      .Member("steps", motion.frontend_steps);
  OptionalMember("sigma_t", motion.frontend_sigma_t, json);
  OptionalMember("sigma_r", motion.frontend_sigma_r, json);
  json->EndObject().Key("claims").BeginArray();
  for (const MotionNoiseReport::Group& group : motion.claims) {
    json->BeginObject()
        .Member("stated_sigma_t", group.stated_sigma_t)
        .Member("stated_sigma_r", group.stated_sigma_r)
        .Member("pairs", group.pairs);
    OptionalMember("scale", group.scale, json);
    json->Member("factor", group.factor).EndObject();
  }
  json->EndArray().EndObject();
}

}  // namespace symba::io_internal
