# Pictures: write_png encodes with libpng (Debian: libpng-dev).
# Meant to be included from engine/CMakeLists.txt after add_library(expanse ...).
# The installed package's config must then find_dependency(PNG) for static builds.
include_guard(GLOBAL)
find_package(PNG REQUIRED)
target_link_libraries(expanse PRIVATE PNG::PNG)
