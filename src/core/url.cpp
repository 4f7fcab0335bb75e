#include "core/url.h"

#include <cctype>
#include <filesystem>

namespace parallax {
namespace {

bool startsWithNoCase(std::string_view text, std::string_view prefix) {
  if (text.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(text[i])) != prefix[i]) return false;
  }
  return true;
}

// Where the authority (host, port, user info) starts: after "scheme://".
std::size_t authorityStart(std::string_view url) {
  const std::size_t scheme_end = url.find("://");
  return scheme_end == std::string_view::npos ? 0 : scheme_end + 3;
}

}  // namespace

bool isHttpUrl(std::string_view text) {
  const std::size_t start = startsWithNoCase(text, "http://")    ? 7
                            : startsWithNoCase(text, "https://") ? 8
                                                                 : 0;
  return start > 0 && text.size() > start && text[start] != '/';
}

UrlParts splitUrl(std::string_view url) {
  const std::size_t fragment = url.find('#');
  if (fragment != std::string_view::npos) url = url.substr(0, fragment);
  const std::size_t query = url.find('?', authorityStart(url));
  if (query == std::string_view::npos) return {std::string(url), {}};
  return {std::string(url.substr(0, query)), std::string(url.substr(query))};
}

std::string urlFileName(std::string_view url) {
  const std::string base = splitUrl(url).base;
  const std::size_t authority = authorityStart(base);
  const std::size_t path = base.find('/', authority);
  if (path == std::string::npos) return {};
  return base.substr(base.rfind('/') + 1);
}

std::string fileExtensionOf(std::string_view path_or_url) {
  const std::string name = isHttpUrl(path_or_url)
                               ? urlFileName(path_or_url)
                               : std::filesystem::path(path_or_url).filename().string();
  return std::filesystem::path(name).extension().string();
}

std::string urlForMessages(std::string_view url) {
  if (url.find("://") == std::string_view::npos) return std::string(url);  // a path
  const std::size_t authority = authorityStart(url);
  const std::size_t end = url.find_first_of("/?#", authority);
  const std::string_view host_part = url.substr(
      authority, end == std::string_view::npos ? std::string_view::npos : end - authority);
  const std::size_t at = host_part.rfind('@');
  if (at == std::string_view::npos) return std::string(url);
  return std::string(url.substr(0, authority)) + std::string(url.substr(authority + at + 1));
}

}  // namespace parallax
