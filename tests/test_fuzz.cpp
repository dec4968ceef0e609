// A seeded mutation fuzzer over the committed corpus (tests/fuzz/corpus): every mutant goes
// through the scene, job-file, glTF, mesh-file or image reader (fuzz/fuzz_inputs.h) and must be read or
// refused with an InputError; a crash fails the whole test binary. The seed is fixed, so
// a run is reproducible; tools/dev/fuzz runs the same readers under libFuzzer, ASan and UBSan
// for as long as wanted. Bounded by a number of mutants and a wall-clock cap (~1 minute),
// and nothing about time is asserted.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "fuzz/fuzz_inputs.h"
#include "gpu_fixture.h"

namespace fs = std::filesystem;

namespace {

std::vector<std::string> loadCorpus() {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(fs::path(PENUMBRA_SOURCE_DIR) / "tests" / "fuzz" / "corpus"))
        files.push_back(entry.path());
    std::sort(files.begin(), files.end());  // directory order differs between machines
    std::vector<std::string> corpus;
    for (const fs::path& f : files) {
        std::ifstream in(f, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        corpus.push_back(text.str());
    }
    return corpus;
}

// Tokens that reach the readers' interesting branches: limits, types, glTF fields, paths,
// OBJ and PLY statements, image headers (HDR, PNG chunks, JPEG markers, EXR attributes).
const std::vector<std::string> kTokens = {"[",
                                          "]",
                                          "{",
                                          "}",
                                          "\"",
                                          ",",
                                          ":",
                                          "null",
                                          "true",
                                          "-1",
                                          "0",
                                          "0.5",
                                          "1e8",
                                          "1.000001e8",
                                          "1e20",
                                          "1e999",
                                          "-0",
                                          "4294967296",
                                          "9223372036854775808",
                                          "\"type\"",
                                          "\"sphere\"",
                                          "\"mesh\"",
                                          "\"gltf\"",
                                          "\"point\"",
                                          "\"sweep\"",
                                          "\"values\"",
                                          "\"set\"",
                                          "\"{i}\"",
                                          "\"uri\"",
                                          "\"../x.bin\"",
                                          "\"/etc/passwd\"",
                                          "\"data:application/octet-stream;base64,AAAA\"",
                                          "\"byteLength\"",
                                          "\"count\"",
                                          "\"bufferView\"",
                                          "\"extras\"",
                                          "\"children\"",
                                          "\"mesh\"",
                                          "\"indices\"",
                                          "\"version\"",
                                          "\"1.0\"",
                                          "\\u0000",
                                          "\\\"",
                                          "\nf ",
                                          "\nv ",
                                          "/",
                                          "//",
                                          "-2147483649",
                                          "\nusemtl ",
                                          "\nelement face ",
                                          "\nproperty list uint int vertex_indices",
                                          "\nend_header\n",
                                          "#?RADIANCE\n",
                                          "\n-Y 8 +X 8\n",
                                          std::string("\x02\x02\x00\x08", 4),  // an RLE scanline start
                                          "IHDR",
                                          "IDAT",
                                          "\xff\xd9",
                                          std::string("\xff\xc0\x00\x11\x08", 5),  // a JPEG SOF0 header
                                          "dataWindow",
                                          "penumbra:spp"};

std::string mutate(std::string s, std::mt19937_64& rng) {
    auto pick = [&](size_t n) { return n == 0 ? size_t(0) : size_t(rng() % n); };
    int count = 1 + int(rng() % 6);
    for (int m = 0; m < count; ++m) {
        size_t at = pick(s.size() + 1);
        switch (rng() % 8) {
            case 0:  // flip a bit
                if (!s.empty()) s[pick(s.size())] ^= char(1u << (rng() % 8));
                break;
            case 1:  // a random byte
                if (!s.empty()) s[pick(s.size())] = char(rng());
                break;
            case 2:  // delete a run
                if (!s.empty()) s.erase(pick(s.size()), 1 + pick(16));
                break;
            case 3:  // insert a token
                s.insert(std::min(at, s.size()), kTokens[pick(kTokens.size())]);
                break;
            case 4: {  // duplicate a run (repeats keys, array elements, chunks)
                size_t from = pick(s.size()), len = 1 + pick(64);
                if (from < s.size()) s.insert(std::min(at, s.size()), s.substr(from, len));
                break;
            }
            case 5: {  // replace a number-like run by an extreme value
                static const char* extremes[] = {"1e300", "-1e38", "3.4e38", "2147483648", "0.000001", "65536", "-0.5"};
                s.insert(std::min(at, s.size()), extremes[pick(7)]);
                break;
            }
            case 6:  // deep nesting around the middle of the document
                if (rng() % 8 == 0) {
                    size_t depth = 200 + pick(200);
                    s.insert(std::min(at, s.size()), std::string(depth, '['));
                }
                break;
            default:  // truncate
                if (rng() % 4 == 0) s.resize(at);
                break;
        }
    }
    if (s.size() > (1u << 20)) s.resize(1u << 20);
    return s;
}

}  // namespace

TEST(Fuzz, MutatedCorpusIsReadOrRefusedCleanly) {
    const std::vector<std::string> corpus = loadCorpus();
    ASSERT_GE(corpus.size(), 6u);
    // Every seed is fine as it is.
    for (const std::string& seed : corpus)
        EXPECT_EQ(penumbra::fuzz::readOne(reinterpret_cast<const uint8_t*>(seed.data()), seed.size()), "");

    const size_t mutants = 40000;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    std::mt19937_64 rng(20261201);
    size_t done = 0, failures = 0;
    for (; done < mutants && std::chrono::steady_clock::now() < deadline; ++done) {
        std::string input = mutate(corpus[rng() % corpus.size()], rng);
        std::string problem = penumbra::fuzz::readOne(reinterpret_cast<const uint8_t*>(input.data()), input.size());
        if (problem.empty()) continue;
        auto saved = penumbra::test::outputPath("fuzz-failure-" + std::to_string(done));
        std::ofstream(saved, std::ios::binary) << input;
        ADD_FAILURE() << problem << " (input saved to " << saved << ")";
        if (++failures == 5) break;
    }
    std::printf("fuzz: %zu mutants read\n", done);
    EXPECT_GT(done, 0u);
}
