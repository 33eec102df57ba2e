#pragma once
// A diagnosis as files (diagnosis_files.cc): diagnosis.json (the steps, the
// candidates tried, the effects named, the residual maps, the effect
// library) and the residual maps along the stroke as tables.

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "wearscar/fusion/diagnosis.h"

namespace wearscar::fusion {

// diagnosis.json's contents.
nlohmann::json DiagnosisJson(const std::string& name, const Diagnosis& d);

// diagnosis.json, the residual maps along the stroke before and after
// (residual_map_before.csv, _after.csv) and, where friction along the
// track was fitted, friction_along_track.csv and
// friction_map_along_track.csv: file name and text.
std::vector<std::pair<std::string, std::string>> DiagnosisFiles(
    const std::string& name, const Diagnosis& diagnosis);

}  // namespace wearscar::fusion
