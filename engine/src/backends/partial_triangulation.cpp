#include "backends/partial_triangulation.hpp"

#include "input/parallel.hpp"

namespace expanse::detail {

void allocate_full_triangulation(PartialTriangulation& partial, std::size_t sites, std::size_t hull_sites,
                                 PartialTriangulation* recycled) {
  if (recycled) {
    partial.triangles.swap(recycled->triangles);
    partial.neighbors.swap(recycled->neighbors);
    partial.triangles.clear();
    partial.neighbors.clear();
  }
  const std::size_t full = sites >= 3 ? 2 * sites - hull_sites - 2 : 0;
  const bool fresh_triangles = partial.triangles.capacity() < full, fresh_neighbors = partial.neighbors.capacity() < full;
  reserve_full_triangulation(partial, sites, hull_sites);
  // A fresh page costs more to fault in than to write: all threads fault them in. The resizes
  // then write nothing (IdTriple's value-initialisation leaves the ids unset); until Triangle
  // was an IdTriple, they zeroed 805 MB on one thread per vector at 4096^2.
  if (fresh_triangles) prefault_capacity(partial.triangles);
  if (fresh_neighbors) prefault_capacity(partial.neighbors);
  partial.triangles.resize(full);
  partial.neighbors.resize(full);
}

}  // namespace expanse::detail
