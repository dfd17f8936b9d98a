#pragma once
// Numeric tables in the reference data's CSV form: '#' lines of provenance, a header of
// column names, then rows of numbers. What a case points at for data the solver needs
// at run time (a propeller's open-water curve, a polynomial's coefficients).
#include <map>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace narwhal {

class Table {
 public:
  // Reads `path`; an Error names the file, line and column of anything that is not a
  // number where one belongs, a row of the wrong width, or a table without rows.
  static Table read(const std::string& path);

  const std::string& path() const { return path_; }
  std::size_t rows() const { return rows_; }
  bool has(const std::string& column) const { return columns_.count(column) > 0; }
  // The column's values (an Error naming the file, the column and the columns it has).
  const std::vector<Real>& column(const std::string& name) const;
  // Text columns are kept as text (a polynomial's name, say): its cells in row order.
  const std::vector<std::string>& text(const std::string& name) const;

 private:
  std::string path_;
  std::size_t rows_ = 0;
  std::vector<std::string> names_;
  std::map<std::string, std::vector<Real>> columns_;
  std::map<std::string, std::vector<std::string>> texts_;
};

}  // namespace narwhal
