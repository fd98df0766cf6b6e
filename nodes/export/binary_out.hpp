#pragma once
// Little-endian binary output whatever the host byte order.
#include <cstdint>
#include <cstring>
#include <ostream>

namespace cf {

inline void put_le(std::ostream& os, std::uint64_t bits, int bytes) {
    char b[8];
    for (int k = 0; k < bytes; ++k) b[k] = static_cast<char>((bits >> (8 * k)) & 0xff);
    os.write(b, bytes);
}
inline void put_u8(std::ostream& os, std::uint8_t v) { put_le(os, v, 1); }
inline void put_u16(std::ostream& os, std::uint16_t v) { put_le(os, v, 2); }
inline void put_i32(std::ostream& os, std::int32_t v) { put_le(os, static_cast<std::uint32_t>(v), 4); }
inline void put_u32(std::ostream& os, std::uint32_t v) { put_le(os, v, 4); }
inline void put_f32(std::ostream& os, float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    put_le(os, u, 4);
}
inline void put_f64(std::ostream& os, double v) {
    std::uint64_t u;
    std::memcpy(&u, &v, 8);
    put_le(os, u, 8);
}

}  // namespace cf
