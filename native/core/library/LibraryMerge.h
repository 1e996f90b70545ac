#pragma once
// Merges the library files of one run (farm shards, resumed runs) into a new file.
#include <string>
#include <vector>

namespace mwb {

/// Merges library files of the same run into `output` (which must not exist). Refuses, naming
/// them, files of another run and world indices present in more than one input. Records are
/// copied byte for byte, ordered by world index. Returns warnings from reading the inputs.
/// Throws LibraryError. Keeps no shared state: merges into other files may run on other threads.
std::vector<std::string> merge_libraries(const std::vector<std::string>& inputs, const std::string& output);

}  // namespace mwb
