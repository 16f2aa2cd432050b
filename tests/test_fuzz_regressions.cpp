// Every input a fuzzer ever failed on (tests/fuzz/regressions) and every seed (tests/fuzz/seeds,
// shared/scenes/bad), replayed through exactly the code the libFuzzer harnesses run (fuzz/).
#include "fuzz/fuzz_targets.h"
#include "testing.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

std::vector<std::string> files_in(const std::string& dir) {
    std::vector<std::string> out;
    if (std::filesystem::is_directory(dir))
        for (const auto& e : std::filesystem::directory_iterator(dir))
            if (e.is_regular_file()) out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

std::string bytes_of(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void replay(const std::vector<std::string>& files, void (*target)(const std::uint8_t*, std::size_t)) {
    for (const auto& path : files) {
        CAPTURE(path);
        const std::string b = bytes_of(path);
        CHECK_NOTHROW(target(reinterpret_cast<const std::uint8_t*>(b.data()), b.size()));
    }
}

const std::string fuzz_dir = std::string(ARBOR_SOURCE_DIR) + "/tests/fuzz";

}  // namespace

TEST_CASE("fuzz regressions: OBJ inputs that once failed, and the seeds, load or fail cleanly") {
    const auto regressions = files_in(fuzz_dir + "/regressions/obj");
    CHECK(!regressions.empty());
    replay(regressions, arbor::fuzz::fuzz_obj);
    replay(files_in(fuzz_dir + "/seeds/obj"), arbor::fuzz::fuzz_obj);
    const std::string shared = arbor::testing::shared_scenes_dir();
    if (!shared.empty()) replay(files_in(shared + "/bad"), arbor::fuzz::fuzz_obj);
}

TEST_CASE("fuzz regressions: mesh files of every format (seeds good and broken, regressions) load or fail cleanly") {
    const auto seeds = files_in(fuzz_dir + "/seeds/mesh");
    CHECK(seeds.size() >= 20);
    replay(seeds, arbor::fuzz::fuzz_mesh);
    replay(files_in(fuzz_dir + "/regressions/mesh"), arbor::fuzz::fuzz_mesh);
    replay(files_in(fuzz_dir + "/seeds/obj"), arbor::fuzz::fuzz_mesh);
    const std::string shared = arbor::testing::shared_scenes_dir();
    if (!shared.empty()) replay(files_in(shared + "/bad"), arbor::fuzz::fuzz_mesh);
}

TEST_CASE("fuzz regressions: ray and hit files that once failed are read or refused cleanly") {
    const auto regressions = files_in(fuzz_dir + "/regressions/rays");
    CHECK(!regressions.empty());
    replay(regressions, arbor::fuzz::fuzz_rays);
}

TEST_CASE("fuzz regressions: the viewer's message seeds and regressions parse or are refused cleanly") {
    const auto seeds = files_in(fuzz_dir + "/seeds/view");
    CHECK(seeds.size() >= 4);
    replay(seeds, arbor::fuzz::fuzz_view_message);
    replay(files_in(fuzz_dir + "/regressions/view"), arbor::fuzz::fuzz_view_message);
}

TEST_CASE("fuzz targets: a broken contract is reported, not swallowed") {
    // A ray file whose only ray is valid: no finding. The targets themselves must be able to fail:
    // a loaded OBJ is checked (here: fine), and a FuzzFinding is a logic_error, not an InputError.
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CHECK_NOTHROW(arbor::fuzz::fuzz_obj(reinterpret_cast<const std::uint8_t*>(quad.data()), quad.size()));
    CHECK(std::is_base_of_v<std::logic_error, arbor::fuzz::FuzzFinding>);
}
