#include "pipeline/output.hpp"

#include "input/parallel.hpp"

namespace expanse::detail {

void remap_to_input(std::span<Triangle> triangles, const SiteSet& sites) {
  const std::int32_t* input_index = sites.input_index.data();
  parallel_chunks(triangles.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      for (std::int32_t& v : triangles[t]) v = input_index[v];
    }
  });
}

std::vector<std::int32_t> to_input_indices(const std::vector<std::int32_t>& site_ids, const SiteSet& sites) {
  std::vector<std::int32_t> out(site_ids.size());
  for (std::size_t i = 0; i < site_ids.size(); ++i) out[i] = sites.input_index[site_ids[i]];
  return out;
}

}  // namespace expanse::detail
