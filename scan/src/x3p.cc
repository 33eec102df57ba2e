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

namespace {

// main.xml of the archive, parsed; `doc` owns it.
pugi::xml_node LoadMainXml(const internal::ZipArchive& zip,
                           const std::string& name,
                           pugi::xml_document* doc) {
  const std::string main_xml = zip.Find("main.xml");
  if (main_xml.empty()) {
    throw ScanError(fmt::format(
        "{}: no main.xml in the archive; expected an ISO 5436-2 x3p", name));
  }
  const std::string xml = zip.Read(main_xml, 64u << 20);
  const pugi::xml_parse_result parsed =
      doc->load_buffer(xml.data(), xml.size());
  if (!parsed) {
    throw ScanError(fmt::format("{}: member '{}' byte {}: XML error: {}",
                                name,
                                main_xml,
                                parsed.offset,
                                parsed.description()));
  }
  pugi::xml_node root = doc->first_child();
  if (!root.child("Record1") || !root.child("Record3")) {
    throw ScanError(
        fmt::format("{}: {} lacks Record1 or Record3", name, main_xml));
  }
  return root;
}

// The grid main.xml describes: axes, sizes, and whether it is a profile.
struct Matrix {
  std::string feature;
  Axis cx, cy, cz;
  long long sx = 0, sy = 0;
  int zbytes = 0;
  size_t n() const { return static_cast<size_t>(sx * sy); }
};

Matrix ReadMatrix(const pugi::xml_node& root, const std::string& name) {
  Matrix m;
  const pugi::xml_node r1 = root.child("Record1");
  m.feature = r1.child_value("FeatureType");
  const pugi::xml_node axes = r1.child("Axes");
  m.cx = ParseAxis(axes.child("CX"));
  m.cy = ParseAxis(axes.child("CY"));
  m.cz = ParseAxis(axes.child("CZ"));
  if (m.cx.type != 'I' || (m.feature != "PRF" && m.cy.type != 'I')) {
    throw ScanError(
        fmt::format("{}: absolute X/Y axes (point clouds) are not supported; "
                    "expected incremental CX and CY",
                    name));
  }
  m.zbytes = BytesOf(m.cz.data_type);
  if (m.zbytes == 0) {
    throw ScanError(fmt::format(
        "{}: CZ DataType '{}'; expected I, L, F or D", name, m.cz.data_type));
  }
  const pugi::xml_node dim = root.child("Record3").child("MatrixDimension");
  m.sx = std::strtoll(dim.child_value("SizeX"), nullptr, 10);
  m.sy = std::strtoll(dim.child_value("SizeY"), nullptr, 10);
  const long long sz = std::strtoll(dim.child_value("SizeZ"), nullptr, 10);
  if (m.sx <= 0 || m.sy <= 0 || m.sx > kMaxPixels || m.sy > kMaxPixels ||
      m.sx * m.sy > kMaxPixels) {
    throw ScanError(fmt::format(
        "{}: MatrixDimension {} x {}; expected positive sizes with at "
        "most {} pixels",
        name,
        m.sx,
        m.sy,
        kMaxPixels));
  }
  if (sz > 1) {
    throw ScanError(
        fmt::format("{}: SizeZ = {}; only one layer is supported", name, sz));
  }
  return m;
}

// One stored value of the given type, as a double.
double RawValue(const char* p, char data_type) {
  switch (data_type) {
    case 'I': {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case 'L': {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case 'F': {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
}

// The binary member of DataLink (and valid.bin when linked) into h, in mm;
// +Inf and invalid points are NaN.
void ReadLinkedPoints(const internal::ZipArchive& zip,
                      const pugi::xml_node& link,
                      const Matrix& m,
                      const std::string& name,
                      float* h) {
  const size_t n = m.n();
  const std::string member = zip.Find(link.child_value("PointDataLink"));
  if (member.empty()) {
    throw ScanError(fmt::format("{}: PointDataLink '{}' is not in the archive",
                                name,
                                link.child_value("PointDataLink")));
  }
  const std::string data = zip.Read(member);
  if (data.size() != n * m.zbytes) {
    throw ScanError(
        fmt::format("{}: member '{}' has {} bytes; expected {} for {} x {} "
                    "values of type {}",
                    name,
                    member,
                    data.size(),
                    n * m.zbytes,
                    m.sx,
                    m.sy,
                    m.cz.data_type));
  }
  for (size_t i = 0; i < n; ++i) {
    const double metres =
        ToMetres(m.cz, RawValue(data.data() + i * m.zbytes, m.cz.data_type));
    h[i] = std::isfinite(metres) ? static_cast<float>(metres * 1e3) : NAN;
  }
  const std::string valid_link = link.child_value("ValidPointsLink");
  if (valid_link.empty()) return;
  const std::string vm = zip.Find(valid_link);
  if (vm.empty()) {
    throw ScanError(fmt::format(
        "{}: ValidPointsLink '{}' is not in the archive", name, valid_link));
  }
  const std::string valid = zip.Read(vm, (n + 7) / 8 + 16);
  if (valid.size() < (n + 7) / 8) {
    throw ScanError(
        fmt::format("{}: member '{}' has {} bytes; expected {} (one bit per "
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

// The inline DataList into h, in mm; an empty Datum is invalid.
void ReadListedPoints(const pugi::xml_node& list,
                      const Matrix& m,
                      const std::string& name,
                      float* h) {
  const size_t n = m.n();
  size_t i = 0;
  for (pugi::xml_node d = list.child("Datum"); d; d = d.next_sibling("Datum")) {
    if (i >= n) {
      throw ScanError(fmt::format(
          "{}: DataList holds more than {} Datum entries", name, n));
    }
    const char* text = d.child_value();
    char* end = nullptr;
    const double raw = std::strtod(text, &end);
    h[i++] = (*text && end != text)
                 ? static_cast<float>(ToMetres(m.cz, raw) * 1e3)
                 : NAN;
  }
  if (i != n) {
    throw ScanError(fmt::format(
        "{}: DataList holds {} Datum entries; expected {} x {} = {}",
        name,
        i,
        m.sx,
        m.sy,
        n));
  }
}

}  // namespace

HeightMap ParseX3p(const std::string& bytes,
                   const std::string& name,
                   const ReadScanOptions& options) {
  internal::ZipArchive zip(bytes, name, options);
  pugi::xml_document doc;
  const pugi::xml_node root = LoadMainXml(zip, name, &doc);
  const Matrix m = ReadMatrix(root, name);
  HeightMap map;
  map.Resize(m.sy, m.sx);
  const pugi::xml_node r3 = root.child("Record3");
  if (const pugi::xml_node link = r3.child("DataLink")) {
    ReadLinkedPoints(zip, link, m, name, map.height_mm.data());
  } else if (const pugi::xml_node list = r3.child("DataList")) {
    ReadListedPoints(list, m, name, map.height_mm.data());
  } else {
    throw ScanError(
        fmt::format("{}: Record3 has neither DataLink nor DataList", name));
  }
  map.dx_mm = m.cx.increment * 1e3;
  map.dy_mm = (m.feature == "PRF" ? m.cx.increment : m.cy.increment) * 1e3;
  if (!(map.dx_mm > 0) || !(map.dy_mm > 0)) {
    throw ScanError(
        fmt::format("{}: axis increments {} / {} m; expected positive pitches",
                    name,
                    m.cx.increment,
                    m.cy.increment));
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
