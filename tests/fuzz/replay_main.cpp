// Runs a fuzz target without libFuzzer, as a regular test: every file of the given corpus
// folders, then, for each, every truncation (stepping so about 200 are tried) and 500 random
// single-byte corruptions from a fixed seed.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

uint64_t next(uint64_t& state) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return state >> 33;
}

void run(const std::vector<uint8_t>& input) { LLVMFuzzerTestOneInput(input.data(), input.size()); }

}  // namespace

int main(int argc, char** argv) {
    size_t files = 0, inputs = 0;
    uint64_t state = 20261122;
    for (int a = 1; a < argc; ++a) {
        for (const auto& entry : std::filesystem::directory_iterator(argv[a])) {
            std::ifstream in(entry.path(), std::ios::binary);
            const std::vector<uint8_t> seed((std::istreambuf_iterator<char>(in)), {});
            ++files;
            run(seed);
            const size_t stride = seed.size() / 200 + 1;
            for (size_t cut = 0; cut < seed.size(); cut += stride, ++inputs)
                run(std::vector<uint8_t>(seed.begin(), seed.begin() + static_cast<std::ptrdiff_t>(cut)));
            for (int k = 0; k < 500 && !seed.empty(); ++k, ++inputs) {
                std::vector<uint8_t> copy = seed;
                copy[next(state) % copy.size()] ^= static_cast<uint8_t>(1 + next(state) % 255);
                run(copy);
            }
        }
    }
    std::printf("replayed %zu corpus files and %zu derived inputs without a crash\n", files, inputs);
    return files > 0 ? 0 : 1;
}
