#include "seam/partial_triangulation.hpp"

#include "input/parallel.hpp"

namespace expanse::detail {

void allocate_full_triangulation(PartialTriangulation& partial, std::size_t sites, std::size_t hull_sites) {
  reserve_full_triangulation(partial, sites, hull_sites);
  // A fresh page costs more to fault in than to write: all threads fault them in first. The
  // zeroing itself is std::vector's resize, one thread per vector; the two run side by side
  // (on one thread one after the other: the 2-core VM's alloc_full stage measures both).
  prefault_capacity(partial.triangles);
  prefault_capacity(partial.neighbors);
  parallel_tasks(2, [&](std::size_t vector) {
    if (vector == 0) {
      partial.triangles.resize(partial.triangles.capacity());
    } else {
      partial.neighbors.resize(partial.neighbors.capacity());
    }
  });
}

}  // namespace expanse::detail
