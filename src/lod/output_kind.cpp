// outputKind (output_kind.h).
#include "lod/output_kind.h"

#include <cctype>
#include <string>
#include <system_error>

namespace parallax {

OutputKind outputKind(const std::filesystem::path& output, std::string_view format) {
  if (format == "potree") return OutputKind::kPotree;
  if (format == "copc") return OutputKind::kCopc;
  const std::string text = output.string();
  std::string name = output.filename().string();
  for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (name.size() > 9 && name.ends_with(".copc.laz")) return OutputKind::kCopc;
  if (!text.empty() && text.back() == '/') return OutputKind::kPotree;
  std::error_code ignored;
  if (std::filesystem::is_directory(output, ignored)) return OutputKind::kPotree;
  if (!output.has_extension()) return OutputKind::kPotree;
  return OutputKind::kPointFile;
}

}  // namespace parallax
