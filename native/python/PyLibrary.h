#pragma once
// The Library object of the Python module, shared by the library and query bindings.
#include <pybind11/pybind11.h>

#include <map>
#include <mutex>
#include <shared_mutex>
#include <string>

#include "library/LibraryReader.h"

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

    const LibraryReader& reader() const { return reader_; }
    /// Held while reading the reader without the GIL.
    std::shared_lock<std::shared_mutex> read_lock() const { return std::shared_lock<std::shared_mutex>(appending_); }

private:
    void index_new_worlds(size_t from) {
        for (size_t k = from; k < reader_.worlds().size(); ++k) by_index_[reader_.worlds()[k].world_index] = k;
    }

    LibraryReader reader_;
    std::map<uint64_t, size_t> by_index_;
    mutable std::shared_mutex appending_;
};

}  // namespace mwb::python
