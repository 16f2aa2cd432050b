// .rays/.hits files: round trip, and every malformed file is a clear error before allocation.
#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/rayfile.h"

#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <unistd.h>

using namespace arbor;

namespace {
std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("arbor_test_" + name)).string();
}
std::string header(const char* magic, std::uint32_t version, std::uint64_t n) {
    std::string h(16, '\0');
    std::memcpy(h.data(), magic, 4);
    std::memcpy(h.data() + 4, &version, 4);
    std::memcpy(h.data() + 8, &n, 8);
    return h;
}
std::string error_of(const std::string& path) {
    try {
        (void)engine::read_rays(path);
    } catch (const engine::InputError& e) {
        return e.what();
    }
    return "read";
}
}  // namespace

TEST_CASE("rayfile: rays and hits round trip bit for bit") {
    std::vector<accel::Ray> rays = {{{1, 2, 3}, 0.5f, {0, -0.0f, 1}, 7}, {{-1, 0, 0}, 0, {1, 1, 1}, INFINITY}};
    std::vector<accel::Hit> hits = {{1.5f, 7, 0.25f, 0.5f}, accel::miss_hit};
    const auto rp = temp_path("rt.rays"), hp = temp_path("rt.hits");
    engine::write_rays(rp, rays);
    engine::write_hits(hp, hits);
    CHECK(std::filesystem::file_size(rp) == 16 + 2 * 32);
    const auto r2 = engine::read_rays(rp);
    const auto h2 = engine::read_hits(hp);
    REQUIRE(r2.size() == 2);
    REQUIRE(h2.size() == 2);
    CHECK(std::memcmp(r2.data(), rays.data(), 64) == 0);
    CHECK(std::memcmp(h2.data(), hits.data(), 32) == 0);
    CHECK(std::signbit(r2[0].dir.y));
}

TEST_CASE("rayfile: malformed files are one-line errors naming the file") {
    const auto p = temp_path("bad.rays");
    engine::write_file_atomic(p, header("RAYS", 1, 3) + std::string(2 * 32, '\0'));
    CHECK(error_of(p) == p + ": header says 3 records (112 bytes) but the file holds 80 bytes");
    engine::write_file_atomic(p, header("RAYS", 1, 1) + std::string(2 * 32, '\0'));
    CHECK(error_of(p) == p + ": header says 1 records (48 bytes) but the file holds 80 bytes");
    engine::write_file_atomic(p, header("RAYS", 1, ~0ull));
    CHECK(error_of(p) == p + ": header says 18446744073709551615 records (an impossible size) but the file holds 16 bytes");
    engine::write_file_atomic(p, header("RAYS", 1, 1ull << 40));
    CHECK(error_of(p).find("but the file holds 16 bytes") != std::string::npos);
    engine::write_file_atomic(p, header("HITS", 1, 0));
    CHECK(error_of(p) == p + ": not a ray file (magic is not 'RAYS')");
    engine::write_file_atomic(p, header("RAYS", 2, 0));
    CHECK(error_of(p) == p + ": unsupported version 2 (expected 1)");
    engine::write_file_atomic(p, "RAYS\1");
    CHECK(error_of(p) == p + ": truncated header (5 of 16 bytes)");
    engine::write_file_atomic(p, "");
    CHECK(error_of(p) == p + ": not a ray file (magic is not 'RAYS')");
    CHECK(error_of(p + ".missing").find("cannot open") != std::string::npos);
    engine::write_file_atomic(p, header("RAYS", 1, 0));
    CHECK(error_of(p) == "read");  // an empty ray file is valid
}

TEST_CASE("atomic write: a failed write leaves the old file untouched") {
    const auto p = temp_path("atomic.txt");
    engine::write_file_atomic(p, "old");
    {
        engine::AtomicFile f(p);  // never committed
        engine::write_file_atomic(f.temp_path(), "partial");
    }
    CHECK(engine::read_file(p) == "old");
    CHECK_FALSE(std::filesystem::exists(p + ".tmp-" + std::to_string(::getpid())));
}

TEST_CASE("atomic write: remove_unfinished_files removes the open temporaries only") {
    // What an MPI job stopped mid-write relies on: it ends without unwinding.
    const auto done = temp_path("atomic_done.txt"), open = temp_path("atomic_open.txt");
    engine::AtomicFile committed(done);
    engine::write_file_atomic(committed.temp_path(), "whole");
    committed.commit();
    engine::AtomicFile unfinished(open);
    engine::write_file_atomic(unfinished.temp_path(), "partial");
    REQUIRE(std::filesystem::exists(unfinished.temp_path()));
    engine::remove_unfinished_files();
    CHECK_FALSE(std::filesystem::exists(unfinished.temp_path()));
    CHECK(engine::read_file(done) == "whole");
    CHECK_FALSE(std::filesystem::exists(open));
    std::filesystem::remove(done);
}
