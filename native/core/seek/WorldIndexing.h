#pragma once
// What a PathIndex needs of a stored world: its bodies' polylines, final orientations and metrics.
#include "library/LibraryReader.h"
#include "query/PathIndex.h"

namespace mwb {

/// The index input of `world`, which `reader` read with polylines (ReaderOptions::polyline_hz > 0).
/// The index borrows the world's polylines: the reader must outlive it (a reader never changes or
/// drops a world it has read). Bodies the world does not have get no path. Throws
/// std::invalid_argument without polylines.
IndexedWorldInput indexed_world_input(const LibraryReader& reader, const StoredWorld& world);

}  // namespace mwb
