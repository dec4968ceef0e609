// The penumbra:pieces header attribute: which (seed, sample index range) pieces a merged
// image holds, so that merges of merges can still be checked for reused samples exactly.
#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <string>

#include "image/image.h"

namespace penumbra {

namespace {

// A decimal number of at most 10 digits (the fields are 32-bit ints and their sums).
int64_t readNumber(const std::string& text, size_t& pos) {
    size_t start = pos;
    while (pos < text.size() && std::isdigit(static_cast<unsigned char>(text[pos])) && pos - start < 11) ++pos;
    if (pos == start || pos - start > 10)
        throw std::invalid_argument("expected a number at character " + std::to_string(start + 1));
    return std::stoll(text.substr(start, pos - start));
}

void expect(const std::string& text, size_t& pos, char c) {
    if (pos >= text.size() || text[pos] != c)
        throw std::invalid_argument(std::string("expected '") + c + "' at character " + std::to_string(pos + 1));
    ++pos;
}

}  // namespace

std::string formatSamplePieces(const std::vector<SamplePiece>& pieces) {
    std::string text;
    for (const SamplePiece& p : pieces) {
        if (!text.empty()) text += ',';
        text += std::to_string(p.seed) + ":" + std::to_string(p.first) + "-" + std::to_string(p.end);
    }
    return text;
}

std::vector<SamplePiece> parseSamplePieces(const std::string& text) {
    std::vector<SamplePiece> pieces;
    size_t pos = 0;
    do {
        if (!pieces.empty()) expect(text, pos, ',');
        SamplePiece p;
        p.seed = readNumber(text, pos);
        expect(text, pos, ':');
        p.first = readNumber(text, pos);
        expect(text, pos, '-');
        p.end = readNumber(text, pos);
        if (p.end <= p.first)
            throw std::invalid_argument("empty sample range " + std::to_string(p.first) + "-" + std::to_string(p.end));
        pieces.push_back(p);
    } while (pos < text.size());
    std::vector<SamplePiece> sorted = pieces;
    std::sort(sorted.begin(), sorted.end(), [](const SamplePiece& a, const SamplePiece& b) {
        return a.seed != b.seed ? a.seed < b.seed : a.first < b.first;
    });
    for (size_t i = 1; i < sorted.size(); ++i)
        if (sorted[i].seed == sorted[i - 1].seed && sorted[i].first < sorted[i - 1].end)
            throw std::invalid_argument("pieces overlap at seed " + std::to_string(sorted[i].seed) + " sample " +
                                        std::to_string(sorted[i].first));
    return pieces;
}

std::vector<SamplePiece> samplePiecesOf(const ImageMetadata& meta) {
    if (meta.pieces) return *meta.pieces;
    if (!meta.seed || !meta.spp) return {};
    const int64_t first = meta.sampleOffset.value_or(0);
    return {{*meta.seed, first, first + *meta.spp}};
}

std::vector<SamplePiece> normalizeSamplePieces(std::vector<SamplePiece> pieces) {
    std::sort(pieces.begin(), pieces.end(), [](const SamplePiece& a, const SamplePiece& b) {
        return a.seed != b.seed ? a.seed < b.seed : a.first < b.first;
    });
    std::vector<SamplePiece> joined;
    for (const SamplePiece& p : pieces) {
        if (!joined.empty() && joined.back().seed == p.seed && joined.back().end >= p.first)
            joined.back().end = std::max(joined.back().end, p.end);
        else joined.push_back(p);
    }
    return joined;
}

}  // namespace penumbra
