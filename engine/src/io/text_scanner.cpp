#include "io/text_scanner.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <memory>

#include "expanse/error.hpp"

namespace expanse::io_detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trim_left(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size() && is_space(s[i])) ++i;
  return s.substr(i);
}

// Field text as it appears, shortened so that a garbage megabyte line does not flood stderr.
std::string quoted(std::string_view field) {
  constexpr std::size_t longest = 40;
  // Appended piece by piece: g++ 12 warns (-Wrestrict, falsely) on "'" + std::string(...).
  std::string text(1, '\'');
  text.append(field.substr(0, longest));
  if (field.size() > longest) text.append("...");
  text.push_back('\'');
  return text;
}

}  // namespace

std::string read_whole_file(const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) {
    throw Error(ErrorCode::io_error, path.string() + ": cannot open: " + std::strerror(errno));
  }
  std::string text;
  std::error_code ec;
  auto size = std::filesystem::file_size(path, ec);
  if (!ec) text.reserve(static_cast<std::size_t>(size));
  char chunk[1 << 16];
  for (;;) {
    std::size_t got = std::fread(chunk, 1, sizeof chunk, file.get());
    text.append(chunk, got);
    if (got < sizeof chunk) break;
  }
  if (std::ferror(file.get())) {
    throw Error(ErrorCode::io_error, path.string() + ": cannot read: " + std::strerror(errno));
  }
  return text;
}

bool TextScanner::next_line() {
  while (pos_ < text_.size()) {
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim_left(line);
    if (!line.empty()) {
      rest_ = line;
      return true;
    }
  }
  rest_ = {};
  return false;
}

bool TextScanner::has_field() const { return !trim_left(rest_).empty(); }

std::size_t TextScanner::count_fields() const {
  std::size_t count = 0;
  std::string_view s = rest_;
  for (;;) {
    s = trim_left(s);
    if (s.empty()) return count;
    ++count;
    std::size_t i = 0;
    while (i < s.size() && !is_space(s[i])) ++i;
    s = s.substr(i);
  }
}

std::string_view TextScanner::next_field() {
  rest_ = trim_left(rest_);
  std::size_t i = 0;
  while (i < rest_.size() && !is_space(rest_[i])) ++i;
  std::string_view field = rest_.substr(0, i);
  rest_ = rest_.substr(i);
  return field;
}

std::int64_t TextScanner::integer(std::string_view what) {
  std::string_view field = next_field();
  if (field.empty()) fail("missing " + std::string(what));
  std::string_view digits = field;
  if (digits.size() > 1 && digits.front() == '+') digits.remove_prefix(1);
  std::int64_t value = 0;
  auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) fail(std::string(what) + " " + quoted(field) + " is out of range");
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    fail(std::string(what) + " " + quoted(field) + " is not an integer");
  }
  return value;
}

double TextScanner::real(std::string_view what) {
  std::string_view field = next_field();
  if (field.empty()) fail("missing " + std::string(what));
  std::string_view digits = field;
  // strtod (which Triangle uses) accepts a leading '+'; from_chars does not.
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-') digits.remove_prefix(1);
  double value = 0;
  auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    // Some libraries flag subnormal results as out of range; those are exact enough to keep.
    // Overflow (infinite) and underflow to zero would change the input silently: errors.
    std::string copy(digits);
    double v = std::strtod(copy.c_str(), nullptr);
    if (std::isfinite(v) && v != 0.0) return v;
    fail(std::string(what) + " " + quoted(field) + " is out of the range of a double");
  }
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    fail(std::string(what) + " " + quoted(field) + " is not a number");
  }
  return value;
}

void TextScanner::fail(const std::string& message) const { fail_at(line_, message); }

void TextScanner::fail_at(std::size_t line, const std::string& message) const {
  throw Error(ErrorCode::parse_error, name_ + ":" + std::to_string(line) + ": " + message);
}

}  // namespace expanse::io_detail
