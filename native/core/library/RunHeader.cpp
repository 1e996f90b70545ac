#include "library/RunHeader.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "library/ByteIO.h"

namespace mwb {
namespace {

using nlohmann::json;

json parameters_to_json(const SimulationParameters& p) {
    return {{"duration_s", p.duration_s},
            {"stop_at_rest", p.stop_at_rest},
            {"min_step_hz", p.min_step_hz},
            {"record_hz", p.record_hz},
            {"alpha_linear", p.alpha_linear},
            {"alpha_angular", p.alpha_angular},
            {"lobe_exponent", p.lobe_exponent},
            {"impact_linear_factor", p.impact_linear_factor},
            {"impact_angular_factor", p.impact_angular_factor},
            {"rest_linear_speed", p.rest_linear_speed},
            {"rest_angular_speed", p.rest_angular_speed},
            {"rest_duration_s", p.rest_duration_s},
            {"checkpoint_interval_s", p.checkpoint_interval_s},
            {"max_speed_mps", p.max_speed_mps},
            {"max_distance_m", p.max_distance_m},
            {"perturb", p.perturb},
            {"sleep", p.sleep},
            {"sleep_linear_speed", p.sleep_linear_speed},
            {"sleep_angular_speed", p.sleep_angular_speed},
            {"sleep_delay_s", p.sleep_delay_s}};
}

SimulationParameters parameters_from_json(const json& j) {
    SimulationParameters p;
    p.duration_s = j.at("duration_s").get<double>();
    p.stop_at_rest = j.at("stop_at_rest").get<bool>();
    p.min_step_hz = j.at("min_step_hz").get<double>();
    p.record_hz = j.at("record_hz").get<double>();
    p.alpha_linear = j.at("alpha_linear").get<double>();
    p.alpha_angular = j.at("alpha_angular").get<double>();
    p.lobe_exponent = j.at("lobe_exponent").get<double>();
    p.impact_linear_factor = j.at("impact_linear_factor").get<double>();
    p.impact_angular_factor = j.at("impact_angular_factor").get<double>();
    p.rest_linear_speed = j.at("rest_linear_speed").get<double>();
    p.rest_angular_speed = j.at("rest_angular_speed").get<double>();
    p.rest_duration_s = j.at("rest_duration_s").get<double>();
    p.checkpoint_interval_s = j.at("checkpoint_interval_s").get<double>();
    p.max_speed_mps = j.at("max_speed_mps").get<double>();
    p.max_distance_m = j.at("max_distance_m").get<double>();
    p.perturb = j.at("perturb").get<bool>();
    // Libraries from before sleeping have no sleep fields: their worlds never slept.
    p.sleep = j.value("sleep", false);
    p.sleep_linear_speed = j.value("sleep_linear_speed", p.sleep_linear_speed);
    p.sleep_angular_speed = j.value("sleep_angular_speed", p.sleep_angular_speed);
    p.sleep_delay_s = j.value("sleep_delay_s", p.sleep_delay_s);
    return p;
}

std::string fnv1a_hex(const std::string& text) {
    uint64_t h = 0xCBF29CE484222325ull;
    for (unsigned char c : text) {
        h ^= c;
        h *= 0x100000001B3ull;
    }
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

/// The run without the engine build: what the run hash covers.
json run_to_json(const RunHeader& header) {
    return {{"scene", json::parse(header.scene_json)},
            {"parameters", parameters_to_json(header.parameters)},
            {"codec", {{"position_error_max_m", header.bounds.position_error_max_m},
                       {"rotation_error_max_rad", header.bounds.rotation_error_max_rad}}},
            {"base_seed", header.base_seed}};
}

}  // namespace

std::string run_header_to_json(const RunHeader& header) {
    json j = run_to_json(header);
    if (!header.engine_build.empty()) j["engine"] = header.engine_build;
    return j.dump();
}

RunHeader run_header_from_json(const std::string& text, const std::string& where) {
    try {
        const json j = json::parse(text);
        RunHeader header;
        header.scene_json = j.at("scene").dump();
        header.parameters = parameters_from_json(j.at("parameters"));
        header.bounds.position_error_max_m = j.at("codec").at("position_error_max_m").get<double>();
        header.bounds.rotation_error_max_rad = j.at("codec").at("rotation_error_max_rad").get<double>();
        header.base_seed = j.at("base_seed").get<uint64_t>();
        if (j.contains("engine")) header.engine_build = j.at("engine").get<std::string>();
        return header;
    } catch (const json::exception& error) {
        throw LibraryError(where + ": run header is malformed: " + error.what());
    }
}

std::string run_settings_to_json(const RunHeader& header) {
    json j = parameters_to_json(header.parameters);
    j["position_error_max_m"] = header.bounds.position_error_max_m;
    j["rotation_error_max_deg"] = header.bounds.rotation_error_max_rad * 180 / 3.14159265358979323846;
    j["base_seed"] = header.base_seed;
    return j.dump();
}

std::string run_hash(const RunHeader& header) { return fnv1a_hex(run_to_json(header).dump()); }

std::string scene_hash(const RunHeader& header) { return fnv1a_hex(json::parse(header.scene_json).dump()); }

}  // namespace mwb
