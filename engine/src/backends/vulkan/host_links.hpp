#pragma once
// The adjacency of the per-site layout's output on the host: from the stars in place (CPU
// devices, the host twin of star_links.comp), the pairing of the slots the device left
// unresolved, and the host's part of the device audit.
#include <cstdint>
#include <vector>

#include "backends/partial_triangulation.hpp"

namespace expanse::detail::vk {

/// The host twin of star_links.comp, over the stars in place (`star`: STAR_ROW ints a site;
/// `info`: two ints a site, star info and first output triangle): the same adjacency. Checks
/// every star first, so that a faulty device cannot make the host misbehave.
void link_stars(const std::int32_t* star, const std::int32_t* info, std::size_t n,
                PartialTriangulation& partial);

/// Links the slots listed as unresolved (edges whose two vertices both deferred): the triangle
/// across x->y, if emitted, is listed too with y->x, so pairing the listed slots by edge
/// completes the adjacency.
void pair_unresolved(const std::vector<std::int32_t>& slots, PartialTriangulation& partial);

/// The host's part of the device audit (audit.comp checked every link the device made and
/// listed the open slots, edges inside the hull with no link): the links pair_unresolved made
/// on the host lead to the reverse edge and back, and no edge left open has its reverse open
/// too, as seam/adjacency_audit.cpp's second check. Costs the seam's size, not the mesh's.
bool open_edges_check_out(const std::vector<std::int32_t>& open_slots,
                          const std::vector<std::int32_t>& paired_slots,
                          const PartialTriangulation& partial);

}  // namespace expanse::detail::vk
