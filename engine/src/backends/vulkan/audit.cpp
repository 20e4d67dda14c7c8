// Vulkan structs are value-initialised from their sType alone ({VK_STRUCTURE_TYPE_...}).
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include "backends/vulkan/audit.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>

#include "backends/vulkan/dispatch.hpp"
#include "backends/vulkan/host_links.hpp"
#include "backends/vulkan/host_threads.hpp"
#include "backends/vulkan/shader_registry.hpp"
#include "backends/vulkan/vulkan_backend.hpp"
#include "host_device.h"

namespace expanse::detail::vk {

using namespace shared;

void record_audit(Context& ctx, Recording& rec, std::uint32_t wg, Buffer& triangles,
                  Buffer& neighbors, Buffer& predecessor, Buffer& open_slots, Buffer& counters,
                  std::size_t capacity, std::size_t open_capacity) {
  const std::uint32_t audit_spec[] = {wg};
  Kernel& audit = ctx.kernel("audit", spirv::audit(), 5, sizeof(shared::AuditParams), audit_spec);
  Buffer* bindings[] = {&triangles, &neighbors, &predecessor, &open_slots, &counters};
  audit.bind(bindings);
  shared::AuditParams params{int(capacity), int(open_capacity), 0, 0};
  dispatch_over(ctx, rec, audit, params, params.first, capacity, wg);
  rec.barrier();
}

bool audit_on_device(Context& ctx, const PartialTriangulation& partial, const Hull& hull) {
  std::lock_guard lock(ctx.mutex());
  const std::size_t count = partial.triangles.size();
  if (partial.neighbors.size() != count || count == 0) return false;
  const std::size_t sites = hull.predecessor.size(), open_capacity = count + 16;
  static_assert(sizeof(partial.triangles[0]) == 12 && sizeof(partial.neighbors[0]) == 12);
  Buffer triangles(ctx, bytes_of(count, 12), false), neighbors(ctx, bytes_of(count, 12), false);
  Buffer predecessor(ctx, bytes_of(sites, 4), false), open_slots(ctx, bytes_of(open_capacity, 4), false);
  Buffer counters(ctx, 64, false);
  const VkDeviceSize o_neighbors = bytes_of(count, 12), o_pred = 2 * o_neighbors,
                     o_counters = o_pred + bytes_of(sites, 4);
  Buffer upload(ctx, o_counters + 64, true);
  char* in = static_cast<char*>(upload.mapped());
  std::memcpy(in, partial.triangles.data(), bytes_of(count, 12));
  std::memcpy(in + o_neighbors, partial.neighbors.data(), bytes_of(count, 12));
  std::memcpy(in + o_pred, hull.predecessor.data(), bytes_of(sites, 4));
  std::uint32_t words[16] = {std::uint32_t(count)};
  std::memcpy(in + o_counters, words, sizeof(words));
  Buffer download(ctx, 64 + bytes_of(open_capacity, 4), true);
  Recording rec(ctx);
  rec.copy(upload, triangles, bytes_of(count, 12), 0);
  rec.copy(upload, neighbors, bytes_of(count, 12), o_neighbors);
  rec.copy(upload, predecessor, bytes_of(sites, 4), o_pred);
  rec.copy(upload, counters, 64, o_counters);
  rec.barrier();
  record_audit(ctx, rec, 64, triangles, neighbors, predecessor, open_slots, counters, count, open_capacity);
  rec.copy(counters, download, 64, 0, 0);
  rec.copy(open_slots, download, bytes_of(open_capacity, 4), 0, 64);
  rec.barrier();
  rec.submit();
  std::memcpy(words, download.mapped(), sizeof(words));
  if (words[COUNTER_BAD_LINKS] != 0 || words[COUNTER_OPEN_OVERFLOW] != 0) return false;
  const auto* open = reinterpret_cast<const std::int32_t*>(static_cast<char*>(download.mapped()) + 64);
  return open_edges_check_out(std::vector<std::int32_t>(open, open + words[COUNTER_OPEN_EDGES]), {},
                              partial);
}

}  // namespace expanse::detail::vk
