#pragma once
// What the report's pages share: escaping, numbers, the head and style, a
// figure as an image file beside the page, and the script that says when
// the images have decoded.

#include <nlohmann/json.hpp>
#include <string>

namespace wearscar::report::internal {

std::string Escape(const std::string& s);

// A number at a fmt spec, or "" when it is none or not finite.
std::string Number(const nlohmann::json& j, const char* fmt_spec = "{:.4f}");

// The value at `path` in `j` (null where there is none).
nlohmann::json At(const nlohmann::json& j,
                  std::initializer_list<const char*> path);

// <!DOCTYPE html> to <body>, titled, with the report's style.
// The "made by" line names the build and date of `provenance` (a result's
// provenance: a specimen's page says when its analysis was made, and stays
// the same bytes while it is not analysed again), else this run's.
std::string PageHead(const std::string& title,
                     const nlohmann::json& provenance = nullptr);

// A figure: the image file at `path` shown from a page in `page_dir` by
// its relative path, loaded as it nears the view, with its caption.
std::string ImageTag(const std::string& path,
                     const std::string& page_dir,
                     const std::string& title);

// The path of `path` relative to `dir` (both made absolute first), with
// '/' separators: what a page's link or image names.
std::string RelativeUrl(const std::string& path, const std::string& dir);

// Ends a page: on load, the body's data-load-ms (from the navigation's
// start to the load event), data-images-rendered ("decoded/all"; with
// ?images=all every lazy image is loaded first) and data-layout
// (horizontal overflow, narrowest figure, smallest text; px), read by the
// browser test, scripts/measure-report and anyone scripting the report.
extern const char* const kImagesScript;

}  // namespace wearscar::report::internal
