#pragma once
// A world as stored in a library file: compressed tracks plus everything metrics and refinement
// need. Decoding lives here; encoding is in WorldRecordEncoder.h so readers never pull in the
// motion encoders.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "library/CheckpointBlock.h"
#include "query/BodyMetrics.h"
#include "sim/WorldResult.h"

namespace mwb {

/// Record payload layout versions for worlds; a value never changes meaning.
/// 1: the original layout. 2: adds the refinement lineage (root world, branch steps, bodies).
/// 3: lineage steps add and remove bodies; the world lists the scene bodies it does not have.
/// 4: checkpoints keep each body's quiet time (sleeping).
/// 5: 4's layout; tracks may be of codec format 2 (curved segments), which older builds cannot
///    decode, so they skip such records with a message instead of failing on the tracks.
constexpr uint32_t kWorldRecordVersion = 5;
constexpr uint32_t kOldestWorldRecordVersion = 1;
constexpr uint32_t kRejectionRecordVersion = 1;

/// One body's compressed motion (codec track formats) in a stored world.
struct StoredTrack {
    uint32_t body = 0;  ///< scene body index
    std::vector<uint8_t> position;
    std::vector<uint8_t> rotation;
    double rest_time_s = 0;
    /// Filled in on load from the parent world (a refined world stores only what changed); may
    /// hold fewer or more frames than the world: decoding holds or cuts at the world's length.
    bool inherited = false;
    /// False for a body this world does not have (removed, or added only to other worlds): no
    /// motion, metrics 0; drawing, queries and baking skip it.
    bool present = true;
};

struct StoredWorld {
    uint64_t world_index = 0;
    uint64_t seed = 0;
    int64_t parent_world = -1;   ///< refined worlds: the world they branch from
    double branch_time_s = 0;    ///< refined worlds: where they leave the parent
    double record_hz = 120;
    double step_hz = 240;
    uint32_t first_frame = 0;
    uint32_t frame_count = 0;
    uint32_t scene_body_count = 0;
    double simulated_time_s = 0;
    uint32_t impacts_perturbed = 0;
    std::vector<StoredTrack> tracks;  ///< all bodies, or only the changed ones for refined worlds
    std::vector<ContactEvent> contacts;
    /// Kept deflated as stored: nothing that loads a library reads them (refinement re-simulates
    /// a world's lineage and takes the checkpoints it makes), and inflated on load a staircase
    /// search's 1,832 worlds took 3.7 GB instead of 2.2. decode_checkpoints() inflates them.
    PackedCheckpoints checkpoints;
    std::vector<MetricValues> metrics;  ///< per_body aligned with tracks
    uint64_t root_world = 0;            ///< refined worlds: the sampled world they descend from
    std::vector<RefineStep> lineage;    ///< refined worlds: every refinement from the root, this one last
    std::vector<uint32_t> absent;       ///< scene bodies below scene_body_count this world does not have
    /// Derived on load, not stored: each track's origin path down-sampled for drawing and
    /// queries, every polyline_stride-th frame plus the last, one block per track of
    /// quantized::block_words(polyline_points) words (16 bits per coordinate, see
    /// common/QuantizedPolyline.h); an absent track's block says so.
    std::vector<uint16_t> polyline;
    uint32_t polyline_points = 0;
    uint32_t polyline_stride = 0;
};

struct StoredRejection {
    uint64_t world_index = 0;
    uint64_t seed = 0;
    std::string reason;
};

/// Parses a world record payload of layout `version`; throws LibraryError (naming `where`) on any
/// inconsistency.
StoredWorld decode_world_record(const uint8_t* data, size_t size, uint32_t version, const std::string& where);
/// A stored world's checkpoints, inflated. Throws LibraryError for a damaged block.
std::vector<Checkpoint> decode_checkpoints(const StoredWorld& world);
StoredRejection decode_rejection_record(const uint8_t* data, size_t size, const std::string& where);

}  // namespace mwb
