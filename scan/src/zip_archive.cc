#include "zip_archive.h"

#include <fmt/format.h>
#include <zip.h>

#include "wearscar/scan/height_map.h"

namespace wearscar::scan::internal {

struct ZipArchive::Impl {
  zip_t* zip = nullptr;
};

ZipArchive::ZipArchive(std::string bytes,
                       std::string name,
                       const ReadScanOptions& options)
    : bytes_(std::move(bytes)),
      impl_(new Impl),
      name_(std::move(name)),
      budget_(options) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* src =
      zip_source_buffer_create(bytes_.data(), bytes_.size(), 0, &error);
  if (src != nullptr)
    impl_->zip = zip_open_from_source(src, ZIP_RDONLY, &error);
  if (impl_->zip == nullptr) {
    const std::string why = zip_error_strerror(&error);
    if (src != nullptr) zip_source_free(src);
    zip_error_fini(&error);
    delete impl_;
    // Where: a ZIP ends with its end-of-central-directory record (the
    // signature PK\5\6 within the last 64 KiB); a truncated file has none.
    const std::size_t eocd = bytes_.rfind(std::string("PK\x05\x06", 4));
    const bool has_end =
        eocd != std::string::npos && bytes_.size() - eocd <= std::size_t{65557};
    throw ScanError(fmt::format(
        "{}: not a readable ZIP archive ({}): {}; expected a ZIP container",
        name_,
        why,
        has_end ? fmt::format("its directory at byte {} of {} does not "
                              "describe the members",
                              eocd,
                              bytes_.size())
                : fmt::format("no end-of-central-directory record in its "
                              "last 64 KiB (the archive is {} bytes: "
                              "truncated?)",
                              bytes_.size())));
  }
  zip_error_fini(&error);
}

ZipArchive::~ZipArchive() {
  zip_discard(impl_->zip);
  delete impl_;
}

std::vector<std::string> ZipArchive::Members() const {
  std::vector<std::string> names;
  const zip_int64_t n = zip_get_num_entries(impl_->zip, 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* nm = zip_get_name(impl_->zip, static_cast<zip_uint64_t>(i), 0);
    if (nm != nullptr) names.emplace_back(nm);
  }
  return names;
}

bool ZipArchive::Has(const std::string& member) const {
  return zip_name_locate(impl_->zip, member.c_str(), 0) >= 0;
}

std::string ZipArchive::Find(const std::string& name) const {
  if (Has(name)) return name;
  for (const std::string& m : Members()) {
    if (m.size() > name.size() &&
        m.compare(m.size() - name.size(), name.size(), name) == 0 &&
        m[m.size() - name.size() - 1] == '/' && m.rfind("__MACOSX", 0) != 0) {
      return m;
    }
  }
  return "";
}

std::string ZipArchive::Read(const std::string& member,
                             std::uint64_t cap) const {
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat(impl_->zip, member.c_str(), 0, &st) != 0) {
    throw ScanError(fmt::format("{}: member '{}' is missing", name_, member));
  }
  const std::string where = fmt::format("{}: member '{}'", name_, member);
  if (!(st.valid & ZIP_STAT_SIZE) || !(st.valid & ZIP_STAT_COMP_SIZE)) {
    throw ScanError(where + ": the archive states no size for it");
  }
  // The stated sizes are checked before anything is inflated; the read
  // below then refuses a member that holds more than stated.
  budget_.Check(st.comp_size, st.size, cap, where);
  zip_file_t* f = zip_fopen(impl_->zip, member.c_str(), 0);
  if (f == nullptr) {
    throw ScanError(fmt::format(
        "{}: cannot be opened: {}", where, zip_strerror(impl_->zip)));
  }
  std::string out;
  out.resize(static_cast<size_t>(st.size));
  zip_int64_t got = zip_fread(f, out.data(), out.size());
  // A header that understates the size must not let more through.
  char probe;
  const zip_int64_t extra = got >= 0 ? zip_fread(f, &probe, 1) : 0;
  zip_fclose(f);
  if (got < 0 || static_cast<std::uint64_t>(got) != out.size()) {
    throw ScanError(fmt::format(
        "{}: truncated or corrupt: {} of the {} bytes its header states "
        "could be inflated",
        where,
        got < 0 ? 0 : got,
        out.size()));
  }
  if (extra > 0) {
    throw ScanError(
        fmt::format("{}: holds more data than the {} bytes its header states",
                    where,
                    out.size()));
  }
  budget_.Spend(out.size());
  return out;
}

}  // namespace wearscar::scan::internal
