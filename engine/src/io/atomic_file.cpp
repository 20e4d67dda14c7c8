#include "io/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <system_error>
#include <unistd.h>

#include "expanse/error.hpp"

namespace expanse::io_detail {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const char* what, int err) {
  throw Error(ErrorCode::io_error,
              path.string() + ": " + what + (err ? std::string(": ") + std::strerror(err) : ""));
}

// Unique per process and per call, so concurrent writers (threads or processes) never share one.
std::filesystem::path temp_name_for(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path temp = target;
  temp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  return temp;
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target)
    : target_(std::move(target)), temp_(temp_name_for(target_)) {
  file_ = std::fopen(temp_.c_str(), "wb");
  if (!file_) fail(target_, "cannot create file", errno);
  buffer_.reserve(1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_) {
    std::error_code ignored;
    std::filesystem::remove(temp_, ignored);
  }
}

void AtomicFile::write(std::string_view bytes) {
  if (buffer_.size() + bytes.size() > buffer_.capacity()) flush_buffer();
  if (bytes.size() >= buffer_.capacity()) {
    if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
      fail(target_, "write failed", errno);
    return;
  }
  buffer_.append(bytes);
}

void AtomicFile::flush_buffer() {
  if (buffer_.empty()) return;
  if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
    fail(target_, "write failed", errno);
  buffer_.clear();
}

void AtomicFile::commit() {
  flush_buffer();
  std::FILE* f = file_;
  file_ = nullptr;
  // fclose reports delayed write errors (a full disk often shows up only here).
  if (std::fflush(f) != 0) {
    int err = errno;
    std::fclose(f);
    fail(target_, "write failed", err);
  }
  if (std::fclose(f) != 0) fail(target_, "write failed", errno);
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) fail(target_, ("cannot rename temporary file: " + ec.message()).c_str(), 0);
  committed_ = true;
}

TextWriter& TextWriter::text(std::string_view s) {
  buffer_.append(s);
  return maybe_flush();
}

TextWriter& TextWriter::integer(long long value) {
  char tmp[32];
  auto [end, ec] = std::to_chars(tmp, tmp + sizeof tmp, value);
  buffer_.append(tmp, end);
  return maybe_flush();
}

TextWriter& TextWriter::real(double value) {
  char tmp[64];
  auto [end, ec] = std::to_chars(tmp, tmp + sizeof tmp, value);
  buffer_.append(tmp, end);
  return maybe_flush();
}

void TextWriter::flush() {
  file_.write(buffer_);
  buffer_.clear();
}

void write_file_atomically(const std::filesystem::path& target, std::string_view bytes) {
  AtomicFile file(target);
  file.write(bytes);
  file.commit();
}

}  // namespace expanse::io_detail
