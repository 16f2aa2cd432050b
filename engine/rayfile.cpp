#include "engine/rayfile.h"

#include "engine/error.h"
#include "engine/file_io.h"

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace arbor::engine {

static_assert(std::endian::native == std::endian::little, "rayfile I/O assumes a little-endian host");

namespace {

constexpr std::uint64_t header_bytes = 16;

template <class Record>
std::vector<Record> read_records(const std::string& path, const char (&magic)[5], const char* what) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!f) throw InputError(path, 0, std::string("cannot open (") + std::strerror(errno) + ")");
    unsigned char header[header_bytes];
    const std::size_t got = std::fread(header, 1, header_bytes, f.get());
    if (got < 4 || std::memcmp(header, magic, 4) != 0)
        throw InputError(path, 0, std::string("not a ") + what + " file (magic is not '" + magic + "')");
    if (got < header_bytes) throw InputError(path, 0, "truncated header (" + std::to_string(got) + " of 16 bytes)");
    std::uint32_t version;
    std::uint64_t n;
    std::memcpy(&version, header + 4, 4);
    std::memcpy(&n, header + 8, 8);
    if (version != 1) throw InputError(path, 0, "unsupported version " + std::to_string(version) + " (expected 1)");
    if (std::fseek(f.get(), 0, SEEK_END) != 0) throw InputError(path, 0, "cannot seek (not a regular file?)");
    const long end = std::ftell(f.get());
    if (end < 0) throw InputError(path, 0, "cannot tell the file size");
    const std::uint64_t payload = std::uint64_t(end) - header_bytes;
    if (n > payload / sizeof(Record) || payload != n * sizeof(Record))
        throw InputError(path, 0, "header says " + std::to_string(n) + " records (" +
                                      (n > (std::uint64_t(1) << 58) ? std::string("an impossible size")
                                                                    : std::to_string(header_bytes + n * sizeof(Record)) + " bytes") +
                                      ") but the file holds " + std::to_string(end) + " bytes");
    std::fseek(f.get(), long(header_bytes), SEEK_SET);
    std::vector<Record> out(n);
    if (n && std::fread(out.data(), sizeof(Record), n, f.get()) != n) throw InputError(path, 0, "read error");
    return out;
}

template <class Record>
void write_records(const std::string& path, const char (&magic)[5], std::span<const Record> records) {
    std::string bytes(header_bytes + records.size_bytes(), '\0');
    const std::uint32_t version = 1;
    const std::uint64_t n = records.size();
    std::memcpy(bytes.data(), magic, 4);
    std::memcpy(bytes.data() + 4, &version, 4);
    std::memcpy(bytes.data() + 8, &n, 8);
    if (n) std::memcpy(bytes.data() + header_bytes, records.data(), records.size_bytes());
    write_file_atomic(path, bytes);
}

}  // namespace

std::vector<accel::Ray> read_rays(const std::string& path) { return read_records<accel::Ray>(path, "RAYS", "ray"); }
std::vector<accel::Hit> read_hits(const std::string& path) { return read_records<accel::Hit>(path, "HITS", "hit"); }
void write_rays(const std::string& path, std::span<const accel::Ray> rays) { write_records(path, "RAYS", rays); }
void write_hits(const std::string& path, std::span<const accel::Hit> hits) { write_records(path, "HITS", hits); }

}  // namespace arbor::engine
