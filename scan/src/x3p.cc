#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <pugixml.hpp>

#include "wearscar/scan/formats.h"
#include "wearscar/scan/read_scan.h"
#include "zip_archive.h"

namespace wearscar::scan {
namespace {

struct Axis {
  char type = 'A';       // I incremental, A absolute
  char data_type = 'D';  // I int16, L int32, F float32, D float64
  double increment = 1.0;
  double offset = 0.0;
  bool has_increment = false;
};

Axis ParseAxis(const pugi::xml_node& node) {
  Axis a;
  const std::string type = node.child_value("AxisType");
  const std::string dt = node.child_value("DataType");
  if (!type.empty()) a.type = type[0];
  if (!dt.empty()) a.data_type = dt[0];
  const char* inc = node.child_value("Increment");
  if (*inc) {
    a.increment = std::strtod(inc, nullptr);
    a.has_increment = true;
  }
  const char* off = node.child_value("Offset");
  if (*off) a.offset = std::strtod(off, nullptr);
  return a;
}

int BytesOf(char data_type) {
  switch (data_type) {
    case 'I':
      return 2;
    case 'L':
      return 4;
    case 'F':
      return 4;
    case 'D':
      return 8;
  }
  return 0;
}

// Height in metres of a raw value: integer types carry increment and offset;
// floating types are metres already.
double ToMetres(const Axis& z, double raw) {
  if (z.data_type == 'I' || z.data_type == 'L')
    return raw * z.increment + z.offset;
  return raw;
}

}  // namespace

HeightMap ParseX3p(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options) {
  internal::ZipArchive zip(bytes, name, options);
  const std::string main_xml = zip.Find("main.xml");
  if (main_xml.empty()) {
    throw ScanError(fmt::format(
        "{}: no main.xml in the archive; expected an ISO 5436-2 x3p", name));
  }
  const std::string xml = zip.Read(main_xml, 64u << 20);
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(xml.data(), xml.size());
  if (!parsed) {
    throw ScanError(fmt::format("{}: member '{}' byte {}: XML error: {}",
                                name,
                                main_xml,
                                parsed.offset,
                                parsed.description()));
  }
  pugi::xml_node root = doc.first_child();
  const pugi::xml_node r1 = root.child("Record1");
  const pugi::xml_node r3 = root.child("Record3");
  if (!r1 || !r3) {
    throw ScanError(
        fmt::format("{}: {} lacks Record1 or Record3", name, main_xml));
  }
  const std::string feature = r1.child_value("FeatureType");
  const pugi::xml_node axes = r1.child("Axes");
  const Axis cx = ParseAxis(axes.child("CX")), cy = ParseAxis(axes.child("CY")),
             cz = ParseAxis(axes.child("CZ"));
  if (cx.type != 'I' || (feature != "PRF" && cy.type != 'I')) {
    throw ScanError(
        fmt::format("{}: absolute X/Y axes (point clouds) are not supported; "
                    "expected incremental CX and CY",
                    name));
  }
  const int zbytes = BytesOf(cz.data_type);
  if (zbytes == 0) {
    throw ScanError(fmt::format(
        "{}: CZ DataType '{}'; expected I, L, F or D", name, cz.data_type));
  }
  const pugi::xml_node dim = r3.child("MatrixDimension");
  const long long sx = std::strtoll(dim.child_value("SizeX"), nullptr, 10);
  const long long sy = std::strtoll(dim.child_value("SizeY"), nullptr, 10);
  const long long sz = std::strtoll(dim.child_value("SizeZ"), nullptr, 10);
  if (sx <= 0 || sy <= 0 || sx > kMaxPixels || sy > kMaxPixels ||
      sx * sy > kMaxPixels) {
    throw ScanError(fmt::format(
        "{}: MatrixDimension {} x {}; expected positive sizes with at "
        "most {} pixels",
        name,
        sx,
        sy,
        kMaxPixels));
  }
  if (sz > 1) {
    throw ScanError(
        fmt::format("{}: SizeZ = {}; only one layer is supported", name, sz));
  }
  const size_t n = static_cast<size_t>(sx * sy);
  HeightMap map;
  map.height_mm.resize(sy, sx);
  float* h = map.height_mm.data();
  const pugi::xml_node link = r3.child("DataLink");
  const pugi::xml_node list = r3.child("DataList");
  if (link) {
    const std::string member = zip.Find(link.child_value("PointDataLink"));
    if (member.empty()) {
      throw ScanError(
          fmt::format("{}: PointDataLink '{}' is not in the archive",
                      name,
                      link.child_value("PointDataLink")));
    }
    const std::string data = zip.Read(member);
    if (data.size() != n * zbytes) {
      throw ScanError(
          fmt::format("{}: member '{}' has {} bytes; expected {} for {} x {} "
                      "values of type {}",
                      name,
                      member,
                      data.size(),
                      n * zbytes,
                      sx,
                      sy,
                      cz.data_type));
    }
    for (size_t i = 0; i < n; ++i) {
      const char* p = data.data() + i * zbytes;
      double raw;
      switch (cz.data_type) {
        case 'I': {
          std::int16_t v;
          std::memcpy(&v, p, 2);
          raw = v;
          break;
        }
        case 'L': {
          std::int32_t v;
          std::memcpy(&v, p, 4);
          raw = v;
          break;
        }
        case 'F': {
          float v;
          std::memcpy(&v, p, 4);
          raw = v;
          break;
        }
        default: {
          double v;
          std::memcpy(&v, p, 8);
          raw = v;
        }
      }
      const double m = ToMetres(cz, raw);
      h[i] = std::isfinite(m) ? static_cast<float>(m * 1e3)
                              : NAN;  // +Inf: invalid
    }
    const std::string valid_link = link.child_value("ValidPointsLink");
    if (!valid_link.empty()) {
      const std::string vm = zip.Find(valid_link);
      if (vm.empty()) {
        throw ScanError(
            fmt::format("{}: ValidPointsLink '{}' is not in the archive",
                        name,
                        valid_link));
      }
      const std::string valid = zip.Read(vm, (n + 7) / 8 + 16);
      if (valid.size() < (n + 7) / 8) {
        throw ScanError(fmt::format(
            "{}: member '{}' has {} bytes; expected {} (one bit per "
            "point)",
            name,
            vm,
            valid.size(),
            (n + 7) / 8));
      }
      for (size_t i = 0; i < n; ++i) {
        if (!((static_cast<unsigned char>(valid[i / 8]) >> (i % 8)) & 1))
          h[i] = NAN;
      }
    }
  } else if (list) {
    size_t i = 0;
    for (pugi::xml_node d = list.child("Datum"); d;
         d = d.next_sibling("Datum")) {
      if (i >= n) {
        throw ScanError(fmt::format(
            "{}: DataList holds more than {} Datum entries", name, n));
      }
      const char* text = d.child_value();
      char* end = nullptr;
      const double raw = std::strtod(text, &end);
      h[i++] = (*text && end != text)
                   ? static_cast<float>(ToMetres(cz, raw) * 1e3)
                   : NAN;
    }
    if (i != n) {
      throw ScanError(fmt::format(
          "{}: DataList holds {} Datum entries; expected {} x {} = {}",
          name,
          i,
          sx,
          sy,
          n));
    }
  } else {
    throw ScanError(
        fmt::format("{}: Record3 has neither DataLink nor DataList", name));
  }
  map.dx_mm = cx.increment * 1e3;
  map.dy_mm = (feature == "PRF" ? cx.increment : cy.increment) * 1e3;
  if (!(map.dx_mm > 0) || !(map.dy_mm > 0)) {
    throw ScanError(
        fmt::format("{}: axis increments {} / {} m; expected positive pitches",
                    name,
                    cx.increment,
                    cy.increment));
  }
  SyncValidity(&map);
  map.metadata.source = name;
  map.metadata.format = "x3p";
  const pugi::xml_node r2 = root.child("Record2");
  map.metadata.date = r2.child_value("Date");
  const pugi::xml_node inst = r2.child("Instrument");
  map.metadata.instrument = fmt::format(
      "{} {}", inst.child_value("Manufacturer"), inst.child_value("Model"));
  return map;
}

namespace internal {
ScanFormat X3pFormat() {
  return {"x3p",
          "ISO 5436-2 .x3p",
          "Sensofar, Alicona, Zygo, NIST, OpenFMC and others",
          {".x3p"},
          {"PK\x03\x04"},
          [](std::string_view head, std::string_view) {
            return head.rfind("PK\x03\x04", 0) == 0 ? kDetectMagic : 0;
          },
          &ParseX3p};
}
}  // namespace internal

}  // namespace wearscar::scan
