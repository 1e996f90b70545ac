#include "seek/WorldIndexing.h"

#include <algorithm>
#include <stdexcept>

#include "common/QuantizedPolyline.h"
#include "library/WorldDecoding.h"

namespace mwb {

IndexedWorldInput indexed_world_input(const LibraryReader& reader, const StoredWorld& w,
                                      const std::vector<uint32_t>* only_bodies) {
    if (w.polyline_points == 0) throw std::invalid_argument("open the library with polyline_hz > 0 to index it");
    IndexedWorldInput in;
    in.world_index = w.world_index;
    in.stride = w.polyline_stride;
    in.last_frame = w.frame_count - 1;
    in.record_hz = w.record_hz;
    in.hold_until_s = static_cast<double>(reader.run_last_frame()) / w.record_hz;
    const size_t per_path = quantized::block_words(w.polyline_points);
    for (size_t t = 0; t < w.tracks.size(); ++t) {
        const bool wanted =
            !only_bodies || std::binary_search(only_bodies->begin(), only_bodies->end(), static_cast<uint32_t>(t));
        if (!w.tracks[t].present || !wanted) {
            in.borrowed.emplace_back();
            in.final_orientations.push_back({1, 0, 0, 0});
            continue;
        }
        in.borrowed.push_back({w.polyline.data() + t * per_path, w.polyline_points});
        in.final_orientations.push_back(decode_rotations(w, t, {w.frame_count - 1}).front());
    }
    for (const MetricValues& m : w.metrics) {
        in.metric_names.push_back(m.name);
        in.metric_values.push_back(m.per_body);
    }
    return in;
}

}  // namespace mwb
