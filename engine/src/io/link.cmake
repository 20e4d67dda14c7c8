# Pictures: write_png encodes with libpng (Debian: libpng-dev). Included from engine/CMakeLists.txt.
find_package(PNG REQUIRED)
target_link_libraries(expanse PRIVATE PNG::PNG)
