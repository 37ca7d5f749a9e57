#include "pds_fields.hpp"

namespace vtm::ground::detail {

std::string PdsFields::where(const std::string& scope, const std::string& key) {
    return scope.empty() ? key : key + " in " + scope;
}

std::string PdsFields::missing(const std::string& scope, const std::string& key) const {
    return name + ": PDS label: no " + where(scope, key);
}

std::string PdsFields::bad(const PdsStatement& s, const std::string& reason) const {
    std::string shown = s.value.size() > 80U ? s.value.substr(0, 80) + "..." : s.value;
    return name + ": PDS label line " + std::to_string(s.line) + ": " + where(s.scope, s.key) + " " + reason +
           ", got \"" + shown + "\"";
}

std::string PdsFields::unsignedField(const std::string& scope, const std::string& key, std::uint64_t min_value,
                                     std::uint64_t max_value, std::uint64_t& out) const {
    const PdsStatement* s = label.find(scope, key);
    if (s == nullptr) return missing(scope, key);
    std::uint64_t v = 0;
    if (!pdsUnsigned(s->value, max_value, v) || v < min_value) {
        return bad(*s, "must be an integer " + std::to_string(min_value) + ".." + std::to_string(max_value));
    }
    out = v;
    return "";
}

std::string PdsFields::realsField(const std::string& scope, const std::string& key, std::size_t n,
                                  std::vector<double>& out) const {
    const PdsStatement* s = label.find(scope, key);
    if (s == nullptr) return missing(scope, key);
    if (!pdsReals(s->value, n, out)) return bad(*s, "must be a list of " + std::to_string(n) + " finite numbers");
    return "";
}

std::string pdsCameraModelGroup(const PdsLabel& label) {
    for (const char* group : {"GEOMETRIC_CAMERA_MODEL", "GEOMETRIC_CAMERA_MODEL_PARMS"}) {
        if (label.find(group, "MODEL_TYPE") != nullptr) return group;
    }
    return "";
}

std::string pdsRoverFrameGroup(const PdsLabel& label) {
    for (const std::string& scope : label.scopesWhere("COORDINATE_SYSTEM_NAME", "ROVER_FRAME")) {
        const PdsStatement* ref = label.find(scope, "REFERENCE_COORD_SYSTEM_NAME");
        if (!scope.empty() && ref != nullptr && pdsText(ref->value) == "SITE_FRAME") return scope;
    }
    return "";
}

}  // namespace vtm::ground::detail
