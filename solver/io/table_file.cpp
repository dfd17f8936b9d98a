#include "io/table_file.hpp"

#include <charconv>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "io/text_file.hpp"

namespace narwhal {
namespace {

std::vector<std::string> split_row(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const auto first = cell.find_first_not_of(" \t\r"), last = cell.find_last_not_of(" \t\r");
    cells.push_back(first == std::string::npos ? std::string() : cell.substr(first, last - first + 1));
  }
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

bool parse_number(const std::string& s, Real& value) {
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace

Table Table::read(const std::string& path) {
  Table t;
  t.path_ = path;
  std::stringstream in(read_text_file(path));
  std::string line;
  int line_no = 0;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> row_lines;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (t.names_.empty()) {
      t.names_ = split_row(line);
      continue;
    }
    rows.push_back(split_row(line));
    row_lines.push_back(line_no);
  }
  if (t.names_.empty() || rows.empty()) fail("{}: no header and rows of numbers (a table is '#' lines, a header, rows)", path);
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (rows[r].size() != t.names_.size())
      fail("{}:{}: {} values, the header names {} columns ({})", path, row_lines[r], rows[r].size(), t.names_.size(),
           fmt::join(t.names_, ", "));
  for (std::size_t c = 0; c < t.names_.size(); ++c) {
    std::vector<Real> values(rows.size());
    bool numeric = true;
    for (std::size_t r = 0; r < rows.size() && numeric; ++r) numeric = parse_number(rows[r][c], values[r]);
    if (numeric) {
      t.columns_[t.names_[c]] = std::move(values);
    } else {
      std::vector<std::string> cells;
      for (const auto& row : rows) cells.push_back(row[c]);
      t.texts_[t.names_[c]] = std::move(cells);
    }
  }
  t.rows_ = rows.size();
  return t;
}

const std::vector<Real>& Table::column(const std::string& name) const {
  const auto it = columns_.find(name);
  if (it != columns_.end()) return it->second;
  if (texts_.count(name)) {
    const auto& cells = texts_.at(name);
    std::size_t r = 0;
    Real v = 0.0;
    while (r < cells.size() && parse_number(cells[r], v)) ++r;
    fail("{}: column '{}' row {} is '{}', not a number", path_, name, r + 1, cells[r]);
  }
  fail("{}: no column '{}' (columns: {})", path_, name, fmt::join(names_, ", "));
}

const std::vector<std::string>& Table::text(const std::string& name) const {
  const auto it = texts_.find(name);
  if (it != texts_.end()) return it->second;
  if (columns_.count(name)) fail("{}: column '{}' holds numbers, not text", path_, name);
  fail("{}: no column '{}' (columns: {})", path_, name, fmt::join(names_, ", "));
}

}  // namespace narwhal
