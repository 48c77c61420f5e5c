// Base64 (RFC 4648, with '=' padding): what data URIs and the report's data files carry.
#pragma once

#include <string>
#include <string_view>

namespace rigsim {

std::string Base64Encode(std::string_view bytes);

}  // namespace rigsim
