#include "EngineOptions.h"

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>

namespace mwb {
namespace {

double parse_number(const std::string& flag, const std::string& text) {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(value)) throw UsageError(flag + ": '" + text + "' is not a number");
    return value;
}

uint64_t parse_count(const std::string& flag, const std::string& text) {
    char* end = nullptr;
    if (text.empty() || text[0] == '-') throw UsageError(flag + ": '" + text + "' is not a non-negative integer");
    const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
    if (*end != '\0') throw UsageError(flag + ": '" + text + "' is not a non-negative integer");
    return value;
}

// "A:B" is worlds A .. B-1.
void parse_world_range(const std::string& text, EngineOptions& options) {
    const size_t colon = text.find(':');
    if (colon == std::string::npos) throw UsageError("--worlds: expected A:B (worlds A to B-1), got '" + text + "'");
    const uint64_t first = parse_count("--worlds", text.substr(0, colon));
    const uint64_t end = parse_count("--worlds", text.substr(colon + 1));
    if (end <= first) throw UsageError("--worlds: empty range '" + text + "' (B must be greater than A)");
    options.first_world = first;
    options.world_count = end - first;
}

// "a,b,c" -> {"a", "b", "c"}; names may hold anything but commas.
std::vector<std::string> parse_names(const std::string& flag, const std::string& list) {
    std::vector<std::string> names;
    size_t start = 0;
    while (start <= list.size()) {
        const size_t comma = std::min(list.find(',', start), list.size());
        names.push_back(list.substr(start, comma - start));
        if (names.back().empty()) throw UsageError(flag + ": empty name in '" + list + "'");
        start = comma + 1;
    }
    return names;
}

// The flags each command takes; any other is refused, naming the command.
const std::set<std::string>& flags_of(const std::string& command) {
    static const std::set<std::string> common{"--events", "--progress", "--threads"};
    auto with_common = [](std::set<std::string> own) {
        own.insert(common.begin(), common.end());
        return own;
    };
    static const std::map<std::string, std::set<std::string>> flags{
        {"sample", with_common({"--scene", "--out", "--seed", "--worlds", "--count", "--duration", "--alpha", "--no-perturb",
                                "--no-sleep", "--no-stop-at-rest", "--no-shared-prefix", "--position-error",
                                "--rotation-error", "--in-process", "--world-time-limit"})},
        {"refine", with_common({"--library", "--world", "--bodies", "--time", "--count", "--first-child", "--add",
                                "--remove", "--update", "--scene", "--in-process", "--world-time-limit"})},
        {"seek", with_common({"--library", "--goal", "--want", "--budget-worlds", "--budget-s", "--seed", "--json",
                              "--in-process", "--world-time-limit"})},
        {"info", {"--json", "--events"}},
        {"merge", {"--events"}},
        {"validate", {"--events"}},
    };
    // A worker takes what its supervisor was given, or the library whose run it simulates.
    static const std::set<std::string> worker = [] {
        std::set<std::string> own = flags.at("sample");
        own.insert("--library");
        return own;
    }();
    if (command == "worker") return worker;
    const auto it = flags.find(command);
    static const std::set<std::string> none;
    return it == flags.end() ? none : it->second;
}

bool is_known_flag(const std::string& flag) {
    for (const char* command : {"sample", "refine", "seek", "info"})
        if (flags_of(command).count(flag)) return true;
    return false;
}

}  // namespace

const char* engine_usage() {
    return "usage:\n"
           "  mwb-engine sample --scene SCENE.json --out LIB.mwb [--seed S] [--worlds A:B | --count N]\n"
           "                    [--threads T] [--duration SECONDS] [--alpha A] [--no-perturb] [--no-sleep] [--no-stop-at-rest]\n"
           "                    [--no-shared-prefix] [--position-error METRES] [--rotation-error DEGREES] [--progress]\n"
           "                    [--world-time-limit SECONDS] [--in-process]\n"
           "  mwb-engine refine --library LIB.mwb --world W --bodies I,J --time SECONDS [--count N]\n"
           "                    [--first-child K] [--threads T] [--progress] [--world-time-limit SECONDS] [--in-process]\n"
           "  mwb-engine refine --library LIB.mwb --world W [--add NAME,...] [--update NAME,...] [--scene SCENE.json]\n"
           "                    [--remove NAME,...]\n"
           "                    [--count N] [--first-child K] [--threads T] [--progress]\n"
           "  mwb-engine seek --library LIB.mwb --goal GOAL.json --budget-worlds N [--want K] [--budget-s SECONDS]\n"
           "                  [--seed S] [--threads T] [--progress] [--json] [--world-time-limit SECONDS] [--in-process]\n"
           "  mwb-engine info LIB.mwb [--json]\n"
           "  mwb-engine merge OUT.mwb LIB.mwb...\n"
           "  mwb-engine validate SCENE.json\n"
           "Every command takes --events: JSON-lines events on stdout, and \"cancel\" on stdin stops a run.\n";
}

EngineOptions parse_engine_options(const std::vector<std::string>& args) {
    if (args.empty()) throw UsageError("no command given (sample, refine, seek, info, merge or validate)");
    EngineOptions options;
    options.command = args[0];
    std::vector<std::string> positional;
    const std::set<std::string>& allowed = flags_of(options.command);
    for (size_t i = 1; i < args.size(); ++i) {
        const std::string& flag = args[i];
        if (flag.rfind("--", 0) == 0 && !allowed.empty() && !allowed.count(flag))
            throw UsageError(is_known_flag(flag) ? options.command + " does not take " + flag : "unknown option " + flag);
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(flag + " needs a value");
            return args[++i];
        };
        if (flag == "--scene") options.scene_path = value();
        else if (flag == "--out") options.output_path = value();
        else if (flag == "--seed") options.base_seed = parse_count(flag, value());
        else if (flag == "--worlds") parse_world_range(value(), options);
        else if (flag == "--count") options.world_count = parse_count(flag, value());
        else if (flag == "--threads") options.threads = static_cast<int>(parse_count(flag, value()));
        else if (flag == "--duration") options.run.duration_s = parse_number(flag, value());
        else if (flag == "--alpha") options.run.alpha = parse_number(flag, value());
        else if (flag == "--no-perturb") options.parameters.perturb = false;
        else if (flag == "--no-sleep") options.parameters.sleep = false;
        else if (flag == "--no-stop-at-rest") options.run.stop_at_rest = false;
        else if (flag == "--position-error") options.run.position_error_m = parse_number(flag, value());
        else if (flag == "--rotation-error") options.run.rotation_error_deg = parse_number(flag, value());
        else if (flag == "--progress") options.progress = true;
        else if (flag == "--in-process") options.in_process = true;
        else if (flag == "--no-shared-prefix") options.share_prefix = false;
        else if (flag == "--events") options.events = true;
        else if (flag == "--world-time-limit") options.world_time_limit_s = parse_number(flag, value());
        else if (flag == "--json") options.json = true;
        else if (flag == "--library") options.library_path = value();
        else if (flag == "--goal") options.goal_path = value();
        else if (flag == "--want") options.want = parse_count(flag, value());
        else if (flag == "--budget-worlds") options.budget_worlds = parse_count(flag, value());
        else if (flag == "--budget-s") options.budget_s = parse_number(flag, value());
        else if (flag == "--world") options.parent_world = parse_count(flag, value());
        else if (flag == "--time") options.branch_time_s = parse_number(flag, value());
        else if (flag == "--first-child") options.first_child = static_cast<int64_t>(parse_count(flag, value()));
        else if (flag == "--add") options.add_bodies = parse_names(flag, value());
        else if (flag == "--remove") options.remove_bodies = parse_names(flag, value());
        else if (flag == "--update") options.update_bodies = parse_names(flag, value());
        else if (flag == "--bodies") {
            const std::string list = value();
            size_t start = 0;
            while (start <= list.size()) {
                const size_t comma = std::min(list.find(',', start), list.size());
                options.bodies.push_back(static_cast<uint32_t>(parse_count(flag, list.substr(start, comma - start))));
                start = comma + 1;
            }
        }
        else if (flag.rfind("--", 0) == 0) throw UsageError("unknown option " + flag);
        else positional.push_back(flag);
    }
    // The run's settings reach the parameters and bounds as the module's run_hash sets them.
    options.run.seed = options.base_seed;
    apply_run_settings(options.run, options.parameters, options.bounds);
    if (options.command == "worker" && !options.library_path.empty()) {
        // A library's worker: the library holds the run.
    } else if (options.command == "sample" || options.command == "worker") {
        if (options.scene_path.empty() || options.output_path.empty()) throw UsageError("sample needs --scene and --out");
        if (options.world_count == 0) throw UsageError("--count must be at least 1");
        if (!(options.bounds.position_error_max_m > 0) || !(options.bounds.rotation_error_max_rad > 0))
            throw UsageError("codec error bounds must be positive");
    } else if (options.command == "refine") {
        if (options.library_path.empty()) throw UsageError("refine needs --library");
        const bool changes_scene =
            !options.add_bodies.empty() || !options.remove_bodies.empty() || !options.update_bodies.empty();
        if (changes_scene) {
            if (!options.bodies.empty() || options.branch_time_s >= 0)
                throw UsageError("--add, --remove and --update act from t = 0 on their own; refine the new worlds afterwards");
            if ((!options.add_bodies.empty() || !options.update_bodies.empty()) && options.scene_path.empty())
                throw UsageError("--add and --update need --scene (the scene that defines the objects)");
        } else {
            if (options.bodies.empty()) throw UsageError("refine needs --bodies (or --add / --remove / --update)");
            if (options.branch_time_s < 0) throw UsageError("refine needs --time (seconds, >= 0)");
        }
        if (options.world_count == 0) throw UsageError("--count must be at least 1");
    } else if (options.command == "seek") {
        if (options.library_path.empty() || options.goal_path.empty()) throw UsageError("seek needs --library and --goal");
        if (options.budget_worlds == 0) throw UsageError("seek needs --budget-worlds of at least 1");
        if (options.want == 0) throw UsageError("--want must be at least 1");
        if (options.budget_s < 0) throw UsageError("--budget-s must not be negative");
    } else if (options.command == "info" || options.command == "validate") {
        if (positional.size() != 1) throw UsageError(options.command + " takes exactly one file");
        options.inputs = positional;
    } else if (options.command == "merge") {
        if (positional.size() < 2) throw UsageError("merge needs OUT and at least one input library");
        options.output_path = positional[0];
        options.inputs.assign(positional.begin() + 1, positional.end());
    } else {
        throw UsageError("unknown command '" + options.command + "' (sample, refine, seek, info, merge or validate)");
    }
    return options;
}

}  // namespace mwb
