#pragma once
// What a PathIndex needs of a stored world: its bodies' polylines, final orientations and metrics.
#include "library/LibraryReader.h"
#include "query/PathIndex.h"

namespace mwb {

/// The index input of `world`, which `reader` read with polylines (ReaderOptions::polyline_hz > 0).
/// The index borrows the world's polylines: the reader must outlive it (a reader never changes or
/// drops a world it has read). Bodies the world does not have get no path, nor do those outside
/// `only_bodies` (sorted scene body indices) when it is given: a search scores only the bodies its
/// goal names. Throws std::invalid_argument without polylines.
IndexedWorldInput indexed_world_input(const LibraryReader& reader, const StoredWorld& world,
                                      const std::vector<uint32_t>* only_bodies = nullptr);

}  // namespace mwb
