// Merge bookkeeping (penumbra:pieces): a merged EXR records exactly which (seed, sample
// range) pieces it holds, so merges of merges are checked for reused samples exactly, old
// files without the attribute still read as one piece, and batch resume stays exact.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "gpu_fixture.h"
#include "image/image.h"
#include "render_helpers.h"
#include "test_scenes.h"

using namespace penumbra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) { return test::freshOutputDir("pieces", name); }

std::string q(const fs::path& p) { return test::shellQuoted(p); }

}  // namespace

TEST(MergePieces, FormatAndParseRoundTripAndRefuseMalformedText) {
    const std::vector<SamplePiece> pieces{{0, 0, 4}, {0, 8, 12}, {7, 0, 16}};
    EXPECT_EQ(formatSamplePieces(pieces), "0:0-4,0:8-12,7:0-16");
    EXPECT_EQ(parseSamplePieces("0:0-4,0:8-12,7:0-16"), pieces);
    for (const char* bad :
         {"", "0:0-4,", "0:4-4", "0:5-4", "a:0-4", "0:0-4;1:0-4", "0:0-8,0:4-12", "-1:0-4", "0:0-99999999999"})
        EXPECT_THROW(parseSamplePieces(bad), std::invalid_argument) << bad;
    EXPECT_EQ(normalizeSamplePieces({{0, 8, 12}, {1, 0, 4}, {0, 4, 8}, {0, 0, 4}}),
              (std::vector<SamplePiece>{{0, 0, 12}, {1, 0, 4}}));
}

TEST(MergePieces, MergeOfAMergeChecksTheExactPieces) {
    const Image a0 = test::onePixelPartial(0, 4, 1.0f), a4 = test::onePixelPartial(4, 4, 2.0f),
                a8 = test::onePixelPartial(8, 4, 3.0f);
    const Image m = mergeImages({a0, a8}, {"a0.exr", "a8.exr"});
    ASSERT_TRUE(m.meta.pieces);
    EXPECT_EQ(*m.meta.pieces, (std::vector<SamplePiece>{{0, 0, 4}, {0, 8, 12}}));
    // The existing attributes keep their meaning: total spp, first seed, smallest offset.
    EXPECT_EQ(m.meta.spp, 8);
    EXPECT_EQ(m.meta.seed, 0);
    EXPECT_EQ(m.meta.sampleOffset, 0);

    // a8 again: its samples would count twice.
    try {
        mergeImages({m, a8}, {"m.exr", "a8.exr"});
        ADD_FAILURE() << "merge (merge a0 a8) a8 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("a8.exr: sample indices [8, 12) overlap with m.exr"), std::string::npos)
            << e.what();
    }
    // a4 fills the gap: valid, and the result is all of [0, 12).
    const Image full = mergeImages({m, a4}, {"m.exr", "a4.exr"});
    EXPECT_EQ(full.meta.spp, 12);
    EXPECT_EQ(*full.meta.pieces, (std::vector<SamplePiece>{{0, 0, 12}}));
    EXPECT_FLOAT_EQ(full.rgb[0], (4 * 1.0f + 4 * 2.0f + 4 * 3.0f) / 12);

    // Pieces that do not add up to the spp are a damaged file.
    Image damaged = m;
    damaged.meta.spp = 9;
    EXPECT_THROW(mergeImages({damaged, a4}, {"damaged.exr", "a4.exr"}), InputError);
}

TEST(MergePieces, HeaderRoundTripAndOldFilesReadAsOnePiece) {
    fs::path dir = freshDir("header");
    const Image m = mergeImages({test::onePixelPartial(0, 4, 1.0f), test::onePixelPartial(8, 4, 3.0f)}, {"a0", "a8"});
    writeExr(dir / "m.exr", m);
    const Image back = readExr(dir / "m.exr");
    ASSERT_TRUE(back.meta.pieces);
    EXPECT_EQ(*back.meta.pieces, *m.meta.pieces);

    // A file written before the attribute existed (no penumbra:pieces) is one piece.
    const Image old = test::onePixelPartial(4, 4, 2.0f);
    writeExr(dir / "old.exr", old);
    EXPECT_FALSE(readExr(dir / "old.exr").meta.pieces);
    EXPECT_EQ(samplePiecesOf(readExr(dir / "old.exr").meta), (std::vector<SamplePiece>{{0, 4, 8}}));
    EXPECT_NO_THROW(mergeImages({back, readExr(dir / "old.exr")}, {"m.exr", "old.exr"}));

    // A malformed attribute is bad input naming the file.
    Imf::Header header(1, 1);
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    header.insert("penumbra:spp", Imf::IntAttribute(4));
    header.insert("penumbra:pieces", Imf::StringAttribute("0:0-"));
    float rgb[3] = {1, 1, 1};
    Imf::FrameBuffer frame;
    for (int c = 0; c < 3; ++c)
        frame.insert(c == 0   ? "R"
                     : c == 1 ? "G"
                              : "B",
                     Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb + c), 12, 12));
    {
        Imf::OutputFile file((dir / "bad.exr").c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(1);
    }
    try {
        readExr(dir / "bad.exr");
        ADD_FAILURE() << "malformed penumbra:pieces accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find((dir / "bad.exr").string() + ": penumbra:pieces: "), std::string::npos)
            << e.what();
    }
}

TEST(MergePieces, CommandLineMergeOfMergesEqualsTheFullRender) {
    fs::path dir = freshDir("cli");
    json scene = test::floorAndSphereScene({.width = 12, .height = 8, .integrator = "ao"});
    std::ofstream(dir / "scene.json") << scene.dump();
    const std::string r = "render " + q(dir / "scene.json") + " --quiet --spp 4 ";
    std::string err;
    for (int offset : {0, 4, 8})
        ASSERT_EQ(test::runPenumbra(r + "--set sampler.sample_offset=" + std::to_string(offset) + " -o " +
                                        q(dir / ("a" + std::to_string(offset) + ".exr")),
                                    &err),
                  0)
            << err;
    ASSERT_EQ(test::runPenumbra("render " + q(dir / "scene.json") + " --quiet --spp 12 -o " + q(dir / "full.exr")), 0);
    ASSERT_EQ(
        test::runPenumbra("merge " + q(dir / "a0.exr") + " " + q(dir / "a8.exr") + " -o " + q(dir / "m.exr"), &err), 0)
        << err;
    EXPECT_EQ(
        test::runPenumbra("merge " + q(dir / "m.exr") + " " + q(dir / "a8.exr") + " -o " + q(dir / "twice.exr"), &err),
        2);
    EXPECT_NE(err.find("overlap with"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "twice.exr"));
    ASSERT_EQ(
        test::runPenumbra("merge " + q(dir / "m.exr") + " " + q(dir / "a4.exr") + " -o " + q(dir / "all.exr"), &err), 0)
        << err;
    const Image all = readExr(dir / "all.exr"), full = readExr(dir / "full.exr");
    EXPECT_EQ(all.meta.spp, 12);
    ASSERT_EQ(all.rgb.size(), full.rgb.size());
    for (size_t k = 0; k < full.rgb.size(); ++k)
        ASSERT_NEAR(all.rgb[k], full.rgb[k], 2e-5f * (1.0f + std::abs(full.rgb[k]))) << k;

    // Batch resume: a merged file with the job's spp, seed and offset but other samples
    // ([0,4) and [8,12) of an 8-spp job) is not that job's render: it is rendered again.
    std::ofstream(dir / "jobs.json")
        << json{{"jobs", {{{"scene", "scene.json"}, {"output", "m.exr"}, {"set", {{"sampler.spp", 8}}}}}}}.dump();
    ASSERT_EQ(test::runPenumbra("batch " + q(dir / "jobs.json"), &err), 0) << err;
    EXPECT_NE(err.find("replaced output: other sample pieces"), std::string::npos) << err;
    EXPECT_FALSE(readExr(dir / "m.exr").meta.pieces);
    ASSERT_EQ(test::runPenumbra("batch " + q(dir / "jobs.json"), &err), 0) << err;
    EXPECT_NE(err.find("skipped, already complete"), std::string::npos) << err;
}
