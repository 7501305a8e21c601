// SHA-256 (FIPS 180-4) of a byte string, as lower-case hex: the digests in run manifests, so that
// a user can check a file with `sha256sum`.
#pragma once

#include <string>
#include <string_view>

namespace scw::io {

/// 64 lower-case hex digits, equal to `sha256sum`'s for the same bytes.
std::string Sha256Hex(std::string_view bytes);

}  // namespace scw::io
