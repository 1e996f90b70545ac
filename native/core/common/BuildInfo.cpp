#include "common/BuildInfo.h"

namespace mwb {
namespace {

std::string compiler() {
#if defined(__clang__)
    return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
    return std::string("gcc ") + __VERSION__;
#else
    return "unknown compiler";
#endif
}

std::string floating_point_unit() {
#if defined(__x86_64__) && defined(__FMA__)
    return "x86-64 SSE2 with FMA";
#elif defined(__x86_64__)
    return "x86-64 SSE2";
#elif defined(__aarch64__)
    return "arm64";
#else
    return "other CPU";
#endif
}

}  // namespace

const std::string& engine_build() {
    static const std::string build = std::string("many-worlds ") + MWB_VERSION + "; " + compiler() + "; " +
                                     MWB_ODE_BUILD + "; " + floating_point_unit();
    return build;
}

std::string describe_build(const std::string& recorded) {
    return recorded.empty() ? "an unrecorded engine build (the library predates build records)" : recorded;
}

}  // namespace mwb
