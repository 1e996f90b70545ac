// libFuzzer target: any byte string either parses as a scene or throws SceneError. Anything else
// (another exception, a crash, a sanitizer report) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "scene/SceneJson.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        mwb::scene_from_json(std::string(reinterpret_cast<const char*>(data), size));
    } catch (const mwb::SceneError&) {
    }
    return 0;
}
