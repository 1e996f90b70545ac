#include "library/LibraryMerge.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <sys/stat.h>

#include "common/BuildInfo.h"
#include "library/ByteIO.h"
#include "library/LibraryFormat.h"
#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"

namespace mwb {
namespace {

uint64_t world_index_of(const RawRecord& record) {
    // World and rejection records both start with the world index.
    uint64_t index = 0;
    std::memcpy(&index, record.payload.data(), sizeof index);
    return index;
}

}  // namespace

std::vector<std::string> merge_libraries(const std::vector<std::string>& inputs, const std::string& output) {
    if (inputs.empty()) throw LibraryError("merge: no input libraries");
    struct stat info{};
    if (::stat(output.c_str(), &info) == 0) throw LibraryError(output + ": already exists; merge writes a new file");
    std::vector<LibraryReader> readers;
    std::vector<std::string> warnings;
    for (const std::string& path : inputs) {
        readers.emplace_back(path, ReaderOptions{true, 0});
        const auto& w = readers.back().warnings();
        warnings.insert(warnings.end(), w.begin(), w.end());
        if (run_hash(readers.back().header()) != run_hash(readers.front().header()))
            throw LibraryError("merge: " + path + " is from another run than " + inputs.front() +
                               " (scene, parameters, codec bounds or base seed differ)");
        if (readers.back().header().engine_build != readers.front().header().engine_build)
            warnings.push_back(path + " was sampled by " + describe_build(readers.back().header().engine_build) +
                               ", " + inputs.front() + " by " + describe_build(readers.front().header().engine_build) +
                               ": their worlds may not refine with one engine");
    }
    // Scene revisions come first, as in every input; inputs must agree on them (one may have fewer).
    std::vector<const RawRecord*> revisions;
    const std::string* revisions_from = nullptr;
    for (const LibraryReader& reader : readers) {
        std::vector<const RawRecord*> own;
        for (const RawRecord& record : reader.raw_records())
            if (record.type == kRecordTypeSceneRevision) own.push_back(&record);
        const size_t common = std::min(own.size(), revisions.size());
        for (size_t k = 0; k < common; ++k)
            if (own[k]->payload != revisions[k]->payload)
                throw LibraryError("merge: " + reader.path() + " and " + *revisions_from + " revised the scene differently");
        if (own.size() > revisions.size()) {
            revisions = own;
            revisions_from = &reader.path();
        }
    }
    std::map<uint64_t, std::pair<const RawRecord*, const std::string*>> by_index;
    std::vector<std::string> collisions;
    for (const LibraryReader& reader : readers) {
        for (const RawRecord& record : reader.raw_records()) {
            if (record.type == kRecordTypeSceneRevision) continue;
            const uint64_t index = world_index_of(record);
            auto [it, inserted] = by_index.emplace(index, std::make_pair(&record, &reader.path()));
            if (!inserted)
                collisions.push_back("world " + std::to_string(index) + " in " + *it->second.second + " and " + reader.path());
        }
    }
    if (!collisions.empty()) {
        std::string message = "merge: seeds collide:";
        for (size_t k = 0; k < collisions.size() && k < 20; ++k) message += "\n  " + collisions[k];
        if (collisions.size() > 20) message += "\n  ... and " + std::to_string(collisions.size() - 20) + " more";
        throw LibraryError(message);
    }
    LibraryWriter writer(output, readers.front().header());
    for (const RawRecord* record : revisions) writer.append_record(record->type, record->version, record->payload);
    for (const auto& [index, entry] : by_index) writer.append_record(entry.first->type, entry.first->version, entry.first->payload);
    return warnings;
}

}  // namespace mwb
