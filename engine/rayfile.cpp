#include "engine/rayfile.h"

#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/memory_budget.h"

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace arbor::engine {

static_assert(std::endian::native == std::endian::little, "rayfile I/O assumes a little-endian host");

namespace {

constexpr std::uint64_t header_bytes = 16;

/// Checks the first `got` header bytes against the magic, the version and the total size
/// `total` of the file, and the records against `max_bytes` (0: the machine's memory). Returns N.
template <class Record>
std::uint64_t check_header(const std::string& name, const unsigned char* header, std::size_t got, std::uint64_t total,
                           const char (&magic)[5], const char* what, std::uint64_t max_bytes) {
    if (got < 4 || std::memcmp(header, magic, 4) != 0)
        throw InputError(name, 0, std::string("not a ") + what + " file (magic is not '" + magic + "')");
    if (got < header_bytes) throw InputError(name, 0, "truncated header (" + std::to_string(got) + " of 16 bytes)");
    std::uint32_t version;
    std::uint64_t n;
    std::memcpy(&version, header + 4, 4);
    std::memcpy(&n, header + 8, 8);
    if (version != 1) throw InputError(name, 0, "unsupported version " + std::to_string(version) + " (expected 1)");
    const std::uint64_t payload = total - header_bytes;
    if (n > payload / sizeof(Record) || payload != n * sizeof(Record))
        throw InputError(name, 0, "header says " + std::to_string(n) + " records (" +
                                      (n > (std::uint64_t(1) << 58) ? std::string("an impossible size")
                                                                    : std::to_string(header_bytes + n * sizeof(Record)) + " bytes") +
                                      ") but the file holds " + std::to_string(total) + " bytes");
    const std::uint64_t budget = memory_budget(max_bytes);
    if (payload > budget)
        throw InputError(name, 0, std::to_string(n) + " records need " + format_bytes(payload) + ", more than the " +
                                      format_bytes(budget) + (max_bytes ? " of --max-memory" : " of memory"));
    return n;
}

template <class Record>
std::vector<Record> read_records(const std::string& path, const char (&magic)[5], const char* what, std::uint64_t max_bytes) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), std::fclose);
    if (!f) throw InputError(path, 0, std::string("cannot open (") + std::strerror(errno) + ")");
    unsigned char header[header_bytes];
    const std::size_t got = std::fread(header, 1, header_bytes, f.get());
    if (got >= 4 && std::memcmp(header, magic, 4) == 0 && got == header_bytes) {
        if (std::fseek(f.get(), 0, SEEK_END) != 0) throw InputError(path, 0, "cannot seek (not a regular file?)");
    }
    const long end = got == header_bytes ? std::ftell(f.get()) : long(got);
    if (end < 0) throw InputError(path, 0, "cannot tell the file size");
    // Everything is checked before the records are allocated.
    const std::uint64_t n = check_header<Record>(path, header, got, std::uint64_t(end), magic, what, max_bytes);
    std::fseek(f.get(), long(header_bytes), SEEK_SET);
    std::vector<Record> out(n);
    if (n && std::fread(out.data(), sizeof(Record), n, f.get()) != n) throw InputError(path, 0, "read error");
    return out;
}

template <class Record>
std::vector<Record> parse_records(std::span<const unsigned char> bytes, const std::string& name, const char (&magic)[5],
                                  const char* what) {
    const std::size_t got = std::min<std::size_t>(bytes.size(), header_bytes);
    const std::uint64_t n = check_header<Record>(name, bytes.data(), got, bytes.size(), magic, what, 0);
    std::vector<Record> out(n);
    if (n) std::memcpy(out.data(), bytes.data() + header_bytes, n * sizeof(Record));
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

std::vector<accel::Ray> read_rays(const std::string& path, std::uint64_t max_bytes) {
    return read_records<accel::Ray>(path, "RAYS", "ray", max_bytes);
}
std::vector<accel::Hit> read_hits(const std::string& path, std::uint64_t max_bytes) {
    return read_records<accel::Hit>(path, "HITS", "hit", max_bytes);
}
std::vector<accel::Ray> parse_rays(std::span<const unsigned char> bytes, const std::string& name) {
    return parse_records<accel::Ray>(bytes, name, "RAYS", "ray");
}
std::vector<accel::Hit> parse_hits(std::span<const unsigned char> bytes, const std::string& name) {
    return parse_records<accel::Hit>(bytes, name, "HITS", "hit");
}
void write_rays(const std::string& path, std::span<const accel::Ray> rays) { write_records(path, "RAYS", rays); }
void write_hits(const std::string& path, std::span<const accel::Hit> hits) { write_records(path, "HITS", hits); }

}  // namespace arbor::engine
