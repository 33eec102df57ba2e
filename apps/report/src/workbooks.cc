// The batch's tables in the formats a lab opens: Excel workbooks written
// by libxlsxwriter, and CSV in a locale's convention (a German Excel reads
// semicolons and decimal commas).

#include "wearscar/report/workbooks.h"

#include <fmt/format.h>
#include <xlsxwriter.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>

#include "wearscar/report/output_folder.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;

// A number as wearscar wrote it: digits, sign, point, exponent only (a
// cell such as "2026-12-06" or "RT" stays text).
bool IsNumber(const std::string& cell, double* value) {
  if (cell.empty() ||
      cell.find_first_not_of("0123456789+-.eE") != std::string::npos)
    return false;
  char* end = nullptr;
  *value = std::strtod(cell.c_str(), &end);
  return end == cell.c_str() + cell.size();
}

}  // namespace

std::vector<std::vector<std::string>> ParseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row(1);
  bool quoted = false, any = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    any = true;
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        row.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        row.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      row.emplace_back();
    } else if (c == '\n') {
      rows.push_back(std::move(row));
      row.assign(1, "");
      any = false;
    } else if (c != '\r') {
      row.back() += c;
    }
  }
  if (any) rows.push_back(std::move(row));
  return rows;
}

std::string LocaleCsv(const std::string& csv, const std::string& locale) {
  if (locale.empty() || locale == "c") return csv;
  std::string out;
  for (const auto& row : ParseCsv(csv)) {
    for (size_t c = 0; c < row.size(); ++c) {
      std::string cell = row[c];
      double unused;
      if (IsNumber(cell, &unused)) {
        for (char& ch : cell)
          if (ch == '.') ch = ',';
      } else if (cell.find_first_of(";\"\n") != std::string::npos) {
        std::string q = "\"";
        for (char ch : cell)
          q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        cell = q + "\"";
      }
      out += (c ? ";" : "") + cell;
    }
    out += "\n";
  }
  return out;
}

void WriteWorkbook(const std::string& path, const std::vector<Sheet>& sheets) {
  // Written beside its place and renamed: no half-written workbook.
  const std::string staging =
      (fs::path(path).parent_path() /
       ("." + fs::path(path).filename().string() + ".partial"))
          .string();
  lxw_workbook* book = workbook_new(staging.c_str());
  if (book == nullptr)
    throw OutputError(fmt::format("{}: cannot create the workbook", path));
  // Dated as the results are (SOURCE_DATE_EPOCH when set: the same bytes
  // for the same results), else now.
  lxw_doc_properties properties = {};
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH"))
    properties.created = static_cast<time_t>(std::strtoll(epoch, nullptr, 10));
  workbook_set_properties(book, &properties);
  lxw_format* head = workbook_add_format(book);
  format_set_bold(head);
  for (const Sheet& sheet : sheets) {
    lxw_worksheet* ws = workbook_add_worksheet(book, sheet.name.c_str());
    const auto rows = ParseCsv(sheet.csv);
    for (size_t r = 0; r < rows.size(); ++r) {
      for (size_t c = 0; c < rows[r].size(); ++c) {
        const std::string& cell = rows[r][c];
        double v;
        const auto row = static_cast<lxw_row_t>(r);
        const auto col = static_cast<lxw_col_t>(c);
        if (r == 0)
          worksheet_write_string(ws, row, col, cell.c_str(), head);
        else if (IsNumber(cell, &v))
          worksheet_write_number(ws, row, col, v, nullptr);
        else if (!cell.empty())
          worksheet_write_string(ws, row, col, cell.c_str(), nullptr);
      }
    }
    if (!rows.empty()) worksheet_freeze_panes(ws, 1, 1);
  }
  const lxw_error error = workbook_close(book);
  if (error != LXW_NO_ERROR) {
    std::remove(staging.c_str());
    throw OutputError(fmt::format(
        "{}: cannot write the workbook ({})", path, lxw_strerror(error)));
  }
  std::error_code ec;
  fs::rename(staging, path, ec);
  if (ec) {
    std::remove(staging.c_str());
    throw OutputError(fmt::format("{}: {}", path, ec.message()));
  }
}

}  // namespace wearscar::report
