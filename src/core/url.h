// http(s) URLs as the command line and the readers see them: recognising one, naming a file
// beside it, and a form fit for messages. Not a general URL parser: libcurl parses what it fetches.
#pragma once

#include <string>
#include <string_view>

namespace parallax {

// True for "http://..." and "https://..." (the scheme in any case), with something after "//".
bool isHttpUrl(std::string_view text);

// The URL without its query ("?...") and fragment ("#..."), and the query with its "?" (empty
// when none). A directory URL keeps its query for the files beside it: object stores sign a whole
// container with one token.
struct UrlParts {
  std::string base;   // scheme://authority/path
  std::string query;  // "?..." or empty
};
UrlParts splitUrl(std::string_view url);

// The path's last segment ("metadata.json" of ".../cloud/metadata.json"; empty for ".../").
std::string urlFileName(std::string_view url);

// The extension of a local path's file name, or of an http(s) URL's last path segment without
// its query and fragment (".pcd" of ".../scan.pcd?X-Amz-Signature=..."), with its dot, as
// written; empty when there is none. What names a file's format where its content does not.
std::string fileExtensionOf(std::string_view path_or_url);

// `url` with "user:password@" removed, for messages and logs (a URL with credentials must not
// end up in a terminal's scroll-back or a bug report). Anything without "://" comes back as is.
std::string urlForMessages(std::string_view url);

}  // namespace parallax
