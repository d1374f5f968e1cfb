// CsvTable: by-name columns and error messages that name the file, line and column.
#include "squint/io/csv.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "squint/core/error.hpp"

namespace squint::io {
namespace {
std::vector<std::string> SplitRow(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (char c : line) {
    if (c == ',') {
      cells.push_back(cell);
      cell.clear();
    } else if (c != '\r') {
      cell.push_back(c);
    }
  }
  cells.push_back(cell);
  for (auto& s : cells) {  // trim spaces
    const auto b = s.find_first_not_of(" \t");
    const auto e = s.find_last_not_of(" \t");
    s = b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  }
  return cells;
}
}  // namespace

CsvTable CsvTable::Read(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open file");
  CsvTable t;
  t.path_ = path;
  std::string line;
  std::size_t line_no = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    auto cells = SplitRow(line);
    if (!have_header) {
      t.header_ = std::move(cells);
      have_header = true;
      for (std::size_t i = 0; i < t.header_.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if (t.header_[i] == t.header_[j])
            throw Error(path.string() + ": line 1: column '" + t.header_[i] + "' appears twice");
      continue;
    }
    if (cells.size() != t.header_.size()) {
      std::ostringstream m;
      m << path.string() << ": line " << line_no << ": " << cells.size() << " cells, the header has "
        << t.header_.size() << " (truncated or malformed row)";
      throw Error(m.str());
    }
    t.rows_.push_back(std::move(cells));
    t.lines_.push_back(line_no);
  }
  if (!have_header) throw Error(path.string() + ": empty file (no header line)");
  return t;
}

std::optional<std::size_t> CsvTable::Find(const std::string& name) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == name) return i;
  return std::nullopt;
}

std::size_t CsvTable::Require(const std::string& name) const {
  auto i = Find(name);
  if (!i) throw Error(path_.string() + ": missing required column '" + name + "'");
  return *i;
}

std::optional<double> CsvTable::Number(std::size_t row, std::size_t col) const {
  const std::string& s = rows_[row][col];
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (*b == '+') ++b;
  auto [p, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || p != e || !std::isfinite(v)) {
    std::ostringstream m;
    m << path_.string() << ": line " << lines_[row] << ": column '" << header_[col] << "': '" << s
      << "' is not a finite number";
    throw Error(m.str());
  }
  return v;
}

double CsvTable::RequireNumber(std::size_t row, std::size_t col) const {
  auto v = Number(row, col);
  if (!v) {
    std::ostringstream m;
    m << path_.string() << ": line " << lines_[row] << ": column '" << header_[col] << "' is empty";
    throw Error(m.str());
  }
  return *v;
}

std::string CsvNumber(double value, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", precision, value);
  std::string s(buf);
  if (s == "-0" || s.find_first_not_of("-0.") == std::string::npos) s = s[0] == '-' ? s.substr(1) : s;
  return s;
}

std::string CsvNumber(const std::optional<double>& value, int precision) {
  return value ? CsvNumber(*value, precision) : std::string();
}

}  // namespace squint::io
