// The secret that keeps other local users out of a `moire serve` page: a random token made
// once per run and carried in every URL of the page (`?token=`). Anyone on the machine can
// reach a port on 127.0.0.1; only whoever was given the URL knows the token.
#pragma once

#include <string>
#include <string_view>

namespace moire::serve {

// 128 bits from std::random_device, as 32 lowercase hex digits.
std::string makeToken();

// Whether `given` is `token`, in a time that does not depend on where they first differ (a
// byte-by-byte comparison that stops early would let a guesser learn the token's prefix).
bool sameToken(std::string_view given, std::string_view token);

} // namespace moire::serve
