#include "WorkerJob.h"

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace mwb {
namespace {

nlohmann::json step_json(const RefineStep& s) {
    return {{"branch_step", s.branch_step}, {"world", s.world_index}, {"bodies", s.bodies},
            {"added", s.added},             {"removed", s.removed}};
}

RefineStep step_from(const nlohmann::json& j) {
    return {j.at("branch_step").get<uint64_t>(), j.at("world").get<uint64_t>(),
            j.at("bodies").get<std::vector<uint32_t>>(), j.at("added").get<std::vector<uint32_t>>(),
            j.at("removed").get<std::vector<uint32_t>>()};
}

}  // namespace

std::string sampled_world_line(uint64_t world_index) { return std::to_string(world_index); }

std::string refined_child_line(const RefinementJob& job, size_t child) {
    nlohmann::json lineage = nlohmann::json::array();
    for (const RefineStep& s : job.lineage) lineage.push_back(step_json(s));
    const nlohmann::json j{{"parent", job.parent_world},       {"root", job.root_world},
                           {"lineage", lineage},               {"parent_frames", job.parent_frames},
                           {"parent_contacts", job.parent_contacts}, {"library_build", job.library_build},
                           {"scene_changed", job.scene_changed},  {"child", step_json(job.children.at(child))}};
    return j.dump();
}

WorkerJob parse_worker_line(const std::string& line) {
    WorkerJob job;
    if (line.empty() || line[0] != '{') {
        size_t used = 0;
        job.world_index = std::stoull(line, &used);
        if (used != line.size()) throw std::invalid_argument("not a world index: " + line);
        return job;
    }
    try {
        const nlohmann::json j = nlohmann::json::parse(line);
        RefinementJob& r = job.refinement;
        r.parent_world = j.at("parent").get<uint64_t>();
        r.root_world = j.at("root").get<uint64_t>();
        for (const nlohmann::json& s : j.at("lineage")) r.lineage.push_back(step_from(s));
        r.parent_frames = j.at("parent_frames").get<uint32_t>();
        r.parent_contacts = j.at("parent_contacts").get<uint64_t>();
        r.library_build = j.at("library_build").get<std::string>();
        r.scene_changed = j.at("scene_changed").get<bool>();
        r.children.push_back(step_from(j.at("child")));
        job.world_index = r.children.front().world_index;
        job.refined = true;
    } catch (const nlohmann::json::exception& error) {
        throw std::invalid_argument(std::string("not a refinement job: ") + error.what());
    }
    return job;
}

}  // namespace mwb
