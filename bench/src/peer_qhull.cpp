// Qhull through its reentrant C API (libqhull_r), driven the way scipy.spatial.Delaunay drives it.
extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <array>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "peers.hpp"
#include "support/timing.hpp"

namespace bench {
namespace {

using expanse::detail::Clock;
using expanse::detail::ms_since;

// Owns one qhT so that every exit path frees Qhull's memory: a leak per repetition would bias
// later repetitions.
class Qhull {
 public:
  Qhull() { qh_zero(&qh_, stderr); }
  ~Qhull() {
    int curlong = 0;
    int totlong = 0;
    qh_freeqhull(&qh_, !qh_ALL);
    qh_memfreeshort(&qh_, &curlong, &totlong);
  }
  Qhull(const Qhull&) = delete;
  Qhull& operator=(const Qhull&) = delete;
  qhT* get() { return &qh_; }

 private:
  qhT qh_{};
};

}  // namespace

PeerRun run_qhull(std::span<const XY> points) {
  static_assert(sizeof(XY) == 2 * sizeof(double), "Qhull reads the points as a flat array");
  PeerRun run;
  Qhull owner;
  qhT* qh = owner.get();

  auto t = Clock::now();
  // scipy's default options for 2D Delaunay ("Qbb Qc Qz Q12"), plus the "Qt" it always adds.
  char command[] = "qhull d Qbb Qc Qz Q12 Qt";
  // Qhull takes a non-const pointer but with ismalloc = False it neither frees nor writes the
  // caller's array (the lifted copy for 'd' is its own).
  auto* coords = const_cast<coordT*>(reinterpret_cast<const coordT*>(points.data()));
  const int code = qh_new_qhull(qh, 2, static_cast<int>(points.size()), coords, False, command,
                                nullptr, stderr);
  if (code != 0) throw std::runtime_error("qhull failed with exit code " + std::to_string(code));
  run.stages_ms.emplace_back("qhull", ms_since(t));

  t = Clock::now();
  facetT* facet = nullptr;
  // Lower facets of the lifted hull are the Delaunay triangles; map Qhull's facet ids to
  // triangle numbers first so that neighbours can be written in one more pass (as scipy does).
  std::vector<std::int32_t> id_map(qh->facet_id, -1);
  std::int32_t count = 0;
  FORALLfacets {
    if (!facet->upperdelaunay) id_map[facet->id] = count++;
  }
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::vector<std::array<std::int32_t, 3>> neighbors;
  triangles.reserve(count);
  neighbors.reserve(count);
  FORALLfacets {
    if (facet->upperdelaunay) continue;
    std::array<std::int32_t, 3> tri{};
    std::array<std::int32_t, 3> across{};
    // For simplicial facets, neighbour i lies across from vertex i.
    for (int i = 0; i < 3; ++i) {
      auto* vertex = static_cast<vertexT*>(facet->vertices->e[i].p);
      auto* neighbor = static_cast<facetT*>(facet->neighbors->e[i].p);
      tri[i] = qh_pointid(qh, vertex->point);
      across[i] = neighbor->upperdelaunay ? -1 : id_map[neighbor->id];
    }
    if (facet->toporient == qh_ORIENTclock) {
      std::swap(tri[0], tri[1]);
      std::swap(across[0], across[1]);
    }
    triangles.push_back(tri);
    neighbors.push_back(across);
  }
  run.stages_ms.emplace_back("extract", ms_since(t));

  for (auto& [name, ms] : run.stages_ms) run.total_ms += ms;
  run.triangles = triangles.size();
  return run;
}

std::string qhull_version() { return std::string("Qhull ") + qh_version; }

}  // namespace bench
