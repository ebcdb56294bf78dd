#pragma once
// Splitting header lines of text formats (PCD, PLY) into whitespace-separated tokens.

#include <string_view>
#include <vector>

namespace fieldlidar::io::detail {

/// Tokens of `line` separated by spaces, tabs or carriage returns (views into `line`).
inline std::vector<std::string_view> split_tokens(std::string_view line) {
  auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !is_space(line[j])) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

}  // namespace fieldlidar::io::detail
