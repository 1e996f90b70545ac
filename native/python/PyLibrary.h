#pragma once
// The Library object of the Python module, shared by the library and query bindings.
#include <pybind11/pybind11.h>

#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>

#include "library/LibraryReader.h"
#include "library/WorldDecoding.h"

namespace mwb::python {

namespace py = pybind11;

// A library opened for browsing: worlds stay compressed in memory and decode on demand.
// Python calls it with the GIL held; work on other threads without the GIL (indexing) reads the
// reader under read_lock(), which poll() excludes while it appends worlds.
class PyLibrary {
public:
    PyLibrary(const std::string& path, double polyline_hz) : reader_(path, ReaderOptions{false, polyline_hz}) {
        index_new_worlds(0);
    }

    size_t poll() {
        const size_t before = reader_.worlds().size();
        size_t added;
        {
            py::gil_scoped_release release;
            std::unique_lock<std::shared_mutex> lock(appending_);
            added = reader_.poll();
            index_new_worlds(before);
        }
        return added;
    }

    const StoredWorld& world(uint64_t world_index) const {
        const StoredWorld* found = find(world_index);
        if (!found) throw py::key_error("no world " + std::to_string(world_index) + " in " + reader_.path());
        return *found;
    }
    /// The world, or nullptr; callable without the GIL under read_lock().
    const StoredWorld* find(uint64_t world_index) const {
        const auto it = by_index_.find(world_index);
        return it == by_index_.end() ? nullptr : &reader_.worlds()[it->second];
    }

    /// One world's tracks decoded whole, (rows, frames, 3) and (rows, frames, 4), rows = the
    /// scene's bodies; kept for the next call on the same world (a preview asks frame after frame).
    struct DecodedWorld {
        uint64_t world_index = 0;
        size_t body_count = 0;  ///< the library's scene bodies when it was decoded
        size_t rows = 0, frames = 0;
        std::vector<double> positions, orientations;
    };
    const DecodedWorld& decoded_world(uint64_t world_index) {
        // Bodies added to the library since (a later poll) give the world more rows.
        if (decoded_ && decoded_->world_index == world_index && decoded_->body_count == reader_.scene_body_count())
            return *decoded_;
        const StoredWorld& w = world(world_index);
        auto next = std::make_unique<DecodedWorld>();
        next->world_index = world_index;
        next->body_count = reader_.scene_body_count();
        {
            py::gil_scoped_release release;
            const auto lock = read_lock();
            const size_t bodies = reader_.scene_body_count();
            next->positions = decode_world_positions(w, bodies);
            next->orientations = decode_world_orientations(w, bodies);
            next->frames = w.frame_count;
            next->rows = w.frame_count ? next->positions.size() / (3 * size_t{w.frame_count}) : 0;
        }
        decoded_ = std::move(next);
        return *decoded_;
    }

    const LibraryReader& reader() const { return reader_; }
    /// Held while reading the reader without the GIL.
    std::shared_lock<std::shared_mutex> read_lock() const { return std::shared_lock<std::shared_mutex>(appending_); }

private:
    void index_new_worlds(size_t from) {
        for (size_t k = from; k < reader_.worlds().size(); ++k) by_index_[reader_.worlds()[k].world_index] = k;
    }

    LibraryReader reader_;
    std::map<uint64_t, size_t> by_index_;
    std::unique_ptr<DecodedWorld> decoded_;  ///< the last world decoded_world() gave
    mutable std::shared_mutex appending_;
};

}  // namespace mwb::python
