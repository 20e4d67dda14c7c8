#pragma once
// Splits a whole text file into content lines and whitespace-separated fields, the way
// Triangle's own reader does: '#' starts a comment that runs to the end of the line, blank
// lines are skipped. Every error names FILE:LINE.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace expanse::io_detail {

/// Reads a whole file into memory. Throws Error(io_error) if it cannot be opened or read.
std::string read_whole_file(const std::filesystem::path& path);

class TextScanner {
 public:
  /// `text` must outlive the scanner.
  TextScanner(std::string name, std::string_view text) : name_(std::move(name)), text_(text) {}

  /// Moves to the next line with content; false at the end of the text.
  bool next_line();
  /// The current line's 1-based number (the last line's number once the text is exhausted).
  std::size_t line_number() const { return line_; }
  /// Fields left on the current line.
  bool has_field() const;
  /// Number of fields left on the current line (does not consume them).
  std::size_t count_fields() const;
  std::string_view next_field();

  /// The next field as an integer; throws parse_error naming `what` if missing or malformed.
  std::int64_t integer(std::string_view what);
  /// The next field as a double (NaN/Inf allowed through; the caller decides).
  double real(std::string_view what);

  /// Throws Error(parse_error, "FILE:LINE: message").
  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void fail_at(std::size_t line, const std::string& message) const;

 private:
  std::string name_;
  std::string_view text_;
  std::size_t pos_ = 0;       // start of the next unread line
  std::size_t line_ = 0;      // number of the current line
  std::string_view rest_;     // unread part of the current line, comment removed
};

}  // namespace expanse::io_detail
