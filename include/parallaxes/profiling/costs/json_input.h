// Reading the costs layer's JSON files (the cost model, calibration sets):
// the document parsed and required to be an object, errors naming the file.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "parallaxes/core/result.h"

namespace px::profiling {

// `what` names the kind of file in the error ("the cost model").
inline Result<nlohmann::json> parse_json_object(const std::string& text, const std::string& where, const std::string& what) {
    nlohmann::json root;
    try {
        root = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        return make_error(where + ": not JSON: " + e.what());
    }
    if (!root.is_object()) return make_error(where + ": " + what + " must be a JSON object");
    return root;
}

}  // namespace px::profiling
