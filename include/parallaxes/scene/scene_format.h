// Formatting shared by the scene's JSON reader and its validation: JSON
// paths and numbers as the error messages print them. Internal to scene/.
#pragma once

#include <cstddef>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace px::scene_format {

inline std::string field_path(const std::string& parent, std::string_view key) {
    std::string out = parent;
    if (!out.empty()) out += '.';
    out += key;
    return out;
}

inline std::string index_path(const std::string& parent, std::size_t i) {
    return parent + "[" + std::to_string(i) + "]";
}

inline std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

template <glm::length_t N>
std::string num(const glm::vec<N, float, glm::defaultp>& v) {
    std::string out = "[";
    for (glm::length_t i = 0; i < N; ++i) out += (i ? ", " : "") + num(v[i]);
    return out + "]";
}

inline std::string joined(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
    return out;
}

}  // namespace px::scene_format
