#pragma once
// The Library object of the Python module, shared by the library and query bindings.
#include <pybind11/pybind11.h>

#include <map>
#include <string>

#include "library/LibraryReader.h"

namespace mwb::python {

namespace py = pybind11;

// A library opened for browsing: worlds stay compressed in memory and decode on demand.
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
            added = reader_.poll();
        }
        index_new_worlds(before);
        return added;
    }

    const StoredWorld& world(uint64_t world_index) const {
        const auto it = by_index_.find(world_index);
        if (it == by_index_.end()) throw py::key_error("no world " + std::to_string(world_index) + " in " + reader_.path());
        return reader_.worlds()[it->second];
    }

    const LibraryReader& reader() const { return reader_; }

private:
    void index_new_worlds(size_t from) {
        for (size_t k = from; k < reader_.worlds().size(); ++k) by_index_[reader_.worlds()[k].world_index] = k;
    }

    LibraryReader reader_;
    std::map<uint64_t, size_t> by_index_;
};

}  // namespace mwb::python
