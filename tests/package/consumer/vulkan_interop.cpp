// Built only when the installed Expanse has its Vulkan backend: the interop header compiles with
// the package's include directories, and its functions link.
#include <expanse/vulkan_interop.hpp>

bool vulkan_interop_links() {
  expanse::vulkan::DeviceHandles handles;  // a real application fills these in
  return handles.device == VK_NULL_HANDLE && expanse::vulkan::max_triangles(10) == 15 &&
         expanse::vulkan::max_index_buffer_bytes(10) == 180;
}
