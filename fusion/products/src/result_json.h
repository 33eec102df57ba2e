#pragma once
// The JSON of a test's products (ResultJson, TrackJson and LevelJson are
// declared in wearscar/fusion/products.h) and of a diagnosis.

#include <nlohmann/json.hpp>
#include <string>

#include "wearscar/fusion/diagnosis.h"

namespace wearscar::fusion::internal {

// diagnosis.json: the steps, the candidates tried, the effects named,
// the residual maps and the effect library.
nlohmann::json DiagnosisJson(const std::string& name, const Diagnosis& d);

}  // namespace wearscar::fusion::internal
