// A small CSV reader that finds columns by name and reports bad cells by file, row and column.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace squint::io {

class CsvTable {
 public:
  // Reads a comma-separated file with one header line. Throws squint::Error when the file is
  // missing or empty, or a row has a different number of cells than the header.
  static CsvTable Read(const std::filesystem::path& path);

  const std::filesystem::path& Path() const { return path_; }
  const std::vector<std::string>& Header() const { return header_; }
  std::size_t Rows() const { return rows_.size(); }

  // Column index by name, or none.
  std::optional<std::size_t> Find(const std::string& name) const;
  // Column index by name; throws squint::Error naming the file when absent.
  std::size_t Require(const std::string& name) const;

  const std::string& Cell(std::size_t row, std::size_t col) const { return rows_[row][col]; }
  // A numeric cell; none when empty. Throws squint::Error naming file, line and column when
  // the cell is not a finite number.
  std::optional<double> Number(std::size_t row, std::size_t col) const;
  // A numeric cell that must be present.
  double RequireNumber(std::size_t row, std::size_t col) const;
  // 1-based line number of a data row in the file (for messages).
  std::size_t LineOf(std::size_t row) const { return lines_[row]; }

 private:
  std::filesystem::path path_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<std::size_t> lines_;
};

// Formats a number for CSV output with fixed precision; trailing zeros kept for alignment.
std::string CsvNumber(double value, int precision = 4);
// Formats an optional number: empty cell when absent.
std::string CsvNumber(const std::optional<double>& value, int precision = 4);

}  // namespace squint::io
