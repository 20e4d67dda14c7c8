#pragma once
// Writes a file so that readers see either nothing or the whole thing: bytes go to a temporary
// file in the target's directory (same file system, so rename is atomic) and are renamed over
// the target only by commit(). Destroying an uncommitted writer removes the temporary file.
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace expanse::io_detail {

class AtomicFile {
 public:
  /// Opens a temporary file beside `target`. Throws Error(io_error) if it cannot.
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Appends bytes (buffered). Throws Error(io_error) on a write failure.
  void write(std::string_view bytes);
  /// Flushes, closes and renames onto the target. Throws Error(io_error) on failure.
  void commit();

 private:
  void flush_buffer();
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::FILE* file_ = nullptr;
  std::string buffer_;
  bool committed_ = false;
};

/// Appends to an AtomicFile in large chunks; numbers are formatted with std::to_chars.
class TextWriter {
 public:
  explicit TextWriter(AtomicFile& file) : file_(file) { buffer_.reserve(kChunk + 128); }
  TextWriter& text(std::string_view s);
  TextWriter& integer(long long value);
  /// Shortest representation that reads back to the same double.
  TextWriter& real(double value);
  TextWriter& space() { return ch(' '); }
  TextWriter& newline() { return ch('\n'); }
  TextWriter& ch(char c) {
    buffer_.push_back(c);
    return maybe_flush();
  }
  /// Hands any buffered text to the file.
  void flush();

 private:
  static constexpr std::size_t kChunk = 1 << 20;
  TextWriter& maybe_flush() {
    if (buffer_.size() >= kChunk) flush();
    return *this;
  }
  AtomicFile& file_;
  std::string buffer_;
};

/// Writes `bytes` to `target` atomically.
void write_file_atomically(const std::filesystem::path& target, std::string_view bytes);

}  // namespace expanse::io_detail
