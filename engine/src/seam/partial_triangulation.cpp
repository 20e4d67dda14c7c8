#include "seam/partial_triangulation.hpp"

#include "input/parallel.hpp"

namespace expanse::detail {

void allocate_full_triangulation(PartialTriangulation& partial, std::size_t sites, std::size_t hull_sites) {
  reserve_full_triangulation(partial, sites, hull_sites);
  // A fresh page costs more to fault in than to write: all threads fault them in. The resizes
  // then write nothing (IdTriple's value-initialisation leaves the ids unset); until Triangle
  // was an IdTriple, they zeroed 805 MB on one thread per vector at 4096^2.
  prefault_capacity(partial.triangles);
  prefault_capacity(partial.neighbors);
  partial.triangles.resize(partial.triangles.capacity());
  partial.neighbors.resize(partial.neighbors.capacity());
}

}  // namespace expanse::detail
