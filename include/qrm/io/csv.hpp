// qrm/io/csv.hpp: results tables as CSV (for machines: numbers round-trip exactly) and as
// Markdown (for people: numbers rounded to a few significant digits).
//
// CSV follows RFC 4180 except that lines end in "\n": a field is quoted when it contains a
// comma, a double quote, CR or LF, or starts or ends with a space or tab, and quotes inside are
// doubled. Real numbers are written as the shortest text that reads back as the same double
// (std::to_chars: 0.1, not 0.10000000000000001), "nan", "inf" or "-inf"; integers exactly.
#pragma once

#include <charconv>
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "atomic_file.hpp"

namespace qrm::io {

// csv_number(v): the shortest text strtod reads back as exactly v, or "nan", "inf", "-inf".
template <int = 0>
inline std::string csv_number(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// csv_quote(field): the field as it appears in a CSV line (quoted only when needed).
template <int = 0>
inline std::string csv_quote(std::string_view field) {
  const bool edge_space = !field.empty() && (field.front() == ' ' || field.front() == '\t' || field.back() == ' ' ||
                                             field.back() == '\t');
  if (!edge_space && field.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(field);
  std::string out = "\"";
  for (char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// cell: one table entry, either text, an integer (kept exact) or a real number.
class cell {
 public:
  enum class kind { text, integer, real };
  cell(std::string_view text) : kind_(kind::text), text_(text) {}
  cell(const char* text) : cell(std::string_view(text)) {}
  cell(const std::string& text) : cell(std::string_view(text)) {}
  template <std::integral T>
    requires(!std::same_as<T, bool> && !std::same_as<T, char>)
  cell(T v) : kind_(kind::integer), text_(std::to_string(v)) {}
  cell(double v) : kind_(kind::real), real_(v) {}
  cell(float v) : cell(static_cast<double>(v)) {}

  kind type() const { return kind_; }
  bool numeric() const { return kind_ != kind::text; }
  // text(): the cell as text, real numbers exactly (csv_number).
  std::string text() const { return kind_ == kind::real ? csv_number(real_) : text_; }
  // text(significant_digits): real numbers rounded to that many significant digits.
  template <int = 0>
  std::string text(int significant_digits) const {
    if (kind_ != kind::real) return text_;
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, real_, std::chars_format::general, significant_digits);
    return std::string(buf, r.ptr);
  }

 private:
  kind kind_;
  std::string text_;
  double real_ = 0;
};

// table: a header and rows of cells, every row as long as the header.
class table {
 public:
  template <int = 0>
  explicit table(std::vector<std::string> header) : header_(std::move(header)) {
    if (header_.empty()) throw std::invalid_argument("table: the header has no columns");
  }
  // add_row(cells): appends a row; std::invalid_argument if its length differs from the header's.
  template <int = 0>
  table& add_row(std::vector<cell> cells) {
    if (cells.size() != header_.size())
      throw std::invalid_argument("table::add_row: row " + std::to_string(rows_.size()) + " has " +
                                  std::to_string(cells.size()) + " cells but the header has " +
                                  std::to_string(header_.size()) + " columns");
    rows_.push_back(std::move(cells));
    return *this;
  }
  const std::vector<std::string>& header() const { return header_; }
  const std::vector<std::vector<cell>>& rows() const { return rows_; }

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<cell>> rows_;
};

// to_csv(t): the header line and one line per row, each ending in "\n".
template <int = 0>
std::string to_csv(const table& t) {
  std::string out;
  auto line = [&out](const auto& fields, auto to_text) {
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (k) out += ',';
      out += csv_quote(to_text(fields[k]));
    }
    out += '\n';
  };
  line(t.header(), [](const std::string& s) { return s; });
  for (const auto& row : t.rows()) line(row, [](const cell& c) { return c.text(); });
  return out;
}

// to_markdown(t, significant_digits): a GitHub-flavoured Markdown table; columns whose cells are
// all numbers are right-aligned, real numbers get `significant_digits` (1..17) significant
// digits, and '|' and '\' in text are escaped. Text with a line break is std::invalid_argument.
template <int = 0>
inline std::string to_markdown(const table& t, int significant_digits = 6) {
  if (significant_digits < 1 || significant_digits > 17)
    throw std::invalid_argument("to_markdown: significant_digits " + std::to_string(significant_digits) +
                                " is not in 1..17");
  auto escape = [](std::string_view s) {
    if (s.find_first_of("\r\n") != std::string_view::npos)
      throw std::invalid_argument("to_markdown: the cell '" + std::string(s) + "' contains a line break");
    std::string r;
    for (char c : s) {
      if (c == '|' || c == '\\') r += '\\';
      r += c;
    }
    return r;
  };
  const std::size_t n = t.header().size();
  std::vector<bool> right(n, !t.rows().empty());
  for (const auto& row : t.rows())
    for (std::size_t k = 0; k < n; ++k) right[k] = right[k] && row[k].numeric();
  std::string out = "|";
  for (const auto& h : t.header()) out.append(" ").append(escape(h)).append(" |");
  out += "\n|";
  for (std::size_t k = 0; k < n; ++k) out += right[k] ? " ---: |" : " --- |";
  out += "\n";
  for (const auto& row : t.rows()) {
    out += "|";
    for (const cell& c : row) out.append(" ").append(escape(c.text(significant_digits))).append(" |");
    out += "\n";
  }
  return out;
}

// write_csv(path, t) / write_markdown(path, t, digits): write the table atomically.
template <int = 0>
void write_csv(const std::filesystem::path& path, const table& t) { write_file_atomically(path, to_csv(t)); }
template <int = 0>
inline void write_markdown(const std::filesystem::path& path, const table& t, int significant_digits = 6) {
  write_file_atomically(path, to_markdown(t, significant_digits));
}

}  // namespace qrm::io

// This header's part of <qrm/io/compiled_io.hpp> (QRM_COMPILED_IO).
#define QRM_DETAIL_CSV_INSTANCES(PREFIX)                                \
  PREFIX std::string to_csv<0>(const table&);                           \
  PREFIX void write_csv<0>(const std::filesystem::path&, const table&);
#ifdef QRM_COMPILED_IO
namespace qrm::io {
QRM_DETAIL_CSV_INSTANCES(extern template)
}  // namespace qrm::io
#endif
