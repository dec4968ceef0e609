// OpenEXR input and output of Penumbra images: R, G, B as 32-bit float plus the
// penumbra:* header attributes of SCENE_FORMAT.md. Reading accepts any pixel type and
// data window, from a file or from bytes in memory through the same checks; every
// OpenEXR failure becomes a one-line InputError naming the file.
#include <OpenEXR/Iex.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "image/atomic_file.h"
#include "image/image.h"

namespace penumbra {

namespace {

constexpr const char* kSpp = "penumbra:spp";
constexpr const char* kSeed = "penumbra:seed";
constexpr const char* kSampleOffset = "penumbra:sample_offset";
constexpr const char* kIntegrator = "penumbra:integrator";
constexpr const char* kRenderSeconds = "penumbra:render_seconds";
constexpr const char* kSampler = "penumbra:sampler";
constexpr const char* kPieces = "penumbra:pieces";
constexpr const char* kChannels[3] = {"R", "G", "B"};

// Far beyond any film we render, small enough that a corrupt header claiming a huge
// data window is refused before we try to allocate it.
constexpr int64_t kMaxPixels = int64_t(1) << 28;

std::string oneLine(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    std::replace(text.begin(), text.end(), '\r', ' ');
    return text;
}

// An EXR file in memory: OpenEXR writes the header, the pixels, then seeks back to fill
// in the offset table.
class MemoryOStream : public Imf::OStream {
public:
    MemoryOStream() : Imf::OStream("memory") {}
    void write(const char c[], int n) override {
        if (m_pos + uint64_t(n) > m_bytes.size()) m_bytes.resize(size_t(m_pos) + size_t(n));
        std::memcpy(m_bytes.data() + m_pos, c, size_t(n));
        m_pos += uint64_t(n);
    }
    uint64_t tellp() override { return m_pos; }
    void seekp(uint64_t pos) override { m_pos = pos; }
    const std::string& bytes() const { return m_bytes; }

private:
    std::string m_bytes;
    uint64_t m_pos = 0;
};

// An EXR file held in memory, read by OpenEXR as it reads a file: OpenEXR's documented way
// to read from memory is an Imf::IStream subclass ("Reading and Writing OpenEXR Image
// Files with the IlmImf Library", Low-Level I/O). As a file's stream does, a read past
// the end throws (Imf::StdIFStream's words), and a seek anywhere is allowed until then.
class MemoryIStream : public Imf::IStream {
public:
    MemoryIStream(std::string_view bytes, const std::string& name) : Imf::IStream(name.c_str()), m_bytes(bytes) {}
    // Returns whether bytes are left after these n, as IStream::read's contract says.
    bool read(char c[], int n) override {
        const uint64_t left = m_pos < m_bytes.size() ? m_bytes.size() - m_pos : 0;
        if (n < 0 || uint64_t(n) > left) throw Iex::InputExc("Unexpected end of file.");
        if (n > 0) std::memcpy(c, m_bytes.data() + m_pos, size_t(n));
        m_pos += uint64_t(n);
        return m_pos < m_bytes.size();
    }
    uint64_t tellg() override { return m_pos; }
    void seekg(uint64_t pos) override { m_pos = pos; }
    void clear() override {}

private:
    std::string_view m_bytes;
    uint64_t m_pos = 0;
};

// Attributes of another type than ours are treated as absent: the file is not ours.
template <class Attr, class Value>
void readAttribute(const Imf::Header& header, const char* name, std::optional<Value>& out) {
    if (const auto* attr = header.findTypedAttribute<Attr>(name)) out = attr->value();
}

// OpenEXR trusts each header attribute's size field and allocates that much before it
// notices the file is shorter: a single corrupt byte can cost gigabytes. Walking the
// header(s) first and checking every size against the file's length avoids that.
void checkAttributeSizes(Imf::IStream& in, int64_t fileSize, const std::string& name) {
    // Reads that would pass the end are refused here, before the stream throws.
    auto readBytes = [&](char* out, int64_t n) {
        if (int64_t(in.tellg()) + n > fileSize) throwInputError(name, "", "truncated or corrupt OpenEXR header");
        in.read(out, int(n));
    };
    in.seekg(0);
    unsigned char start[8] = {};  // magic number and version field; isOpenExrFile has checked both
    readBytes(reinterpret_cast<char*>(start), 8);
    const bool multiPart = start[5] & 0x10;  // version flag bit 12
    auto readName = [&](std::string& out) {
        out.clear();
        for (char c = 0;;) {
            readBytes(&c, 1);
            if (c == '\0') break;
            if (out.size() < 256) out += c;  // long names are at most 255 bytes
        }
    };
    for (;;) {
        std::string attribute, type;
        int attributes = 0;
        for (;; ++attributes) {
            readName(attribute);
            if (attribute.empty()) break;
            readName(type);
            unsigned char size[4];
            readBytes(reinterpret_cast<char*>(size), 4);
            const int32_t bytes = int32_t(uint32_t(size[0]) | uint32_t(size[1]) << 8 | uint32_t(size[2]) << 16 |
                                          uint32_t(size[3]) << 24);
            if (bytes < 0 || int64_t(in.tellg()) + bytes > fileSize)
                throwInputError(name, "", "corrupt OpenEXR header: attribute \"" + attribute + "\" claims " +
                                              std::to_string(bytes) + " bytes");
            in.seekg(in.tellg() + uint64_t(bytes));
        }
        // A single-part file has one header; a multi-part list ends with an empty header.
        if (!multiPart || attributes == 0) break;
    }
}

// Where decodeExrRgba puts the pixels, and who accepts their number first.
struct RgbaTarget {
    std::vector<float>& pixels;
    const std::function<void(uint32_t, uint32_t)>& acceptSize;
};

// The image in `in` (a file or memory, fileSize bytes long), checked before OpenEXR
// allocates anything; InputErrors name `name`. With `rgba`, the pixels go there (4 floats
// a pixel, alpha 1) instead of image.rgb.
Image readExrStream(Imf::IStream& in, int64_t fileSize, const std::string& name, const RgbaTarget* rgba = nullptr) {
    try {
        bool tiled = false, deep = false, multiPart = false;
        in.seekg(0);
        if (!Imf::isOpenExrFile(in, tiled, deep, multiPart)) throwInputError(name, "", "not an OpenEXR file");
        if (deep) throwInputError(name, "", "deep OpenEXR images are not supported");
        checkAttributeSizes(in, fileSize, name);

        // InputFile reads part 0 of multi-part files and tiled files as scanlines.
        in.seekg(0);
        Imf::InputFile file(in);
        const Imf::Header& header = file.header();
        for (const char* c : kChannels)
            if (!header.channels().findChannel(c))
                throwInputError(name, "", std::string("missing channel ") + c + " (need R, G and B)");

        const Imath::Box2i dw = header.dataWindow();
        const int64_t width = int64_t(dw.max.x) - dw.min.x + 1, height = int64_t(dw.max.y) - dw.min.y + 1;
        if (width <= 0 || height <= 0 || width > kMaxPixels / height)
            throwInputError(name, "", "unsupported data window " + std::to_string(width) + "x" + std::to_string(height));

        Image image;
        image.width = uint32_t(width);
        image.height = uint32_t(height);
        float* pixels = nullptr;
        size_t stride = 3;  // floats a pixel
        if (rgba) {
            rgba->acceptSize(image.width, image.height);
            stride = 4;
            rgba->pixels.assign(size_t(width * height) * stride, 1.0f);  // R, G, B overwritten below
            pixels = rgba->pixels.data();
        } else {
            image.rgb.assign(size_t(width * height) * stride, 0.0f);
            pixels = image.rgb.data();
        }
        // Slice::Make offsets the base pointer by the data window's origin, so pixel
        // (min.x, min.y) lands at index 0. Other pixel types convert to float on read.
        Imf::FrameBuffer frame;
        for (int c = 0; c < 3; ++c)
            frame.insert(kChannels[c], Imf::Slice::Make(Imf::FLOAT, pixels + c, dw, stride * sizeof(float),
                                                        size_t(width) * stride * sizeof(float)));
        file.setFrameBuffer(frame);
        file.readPixels(dw.min.y, dw.max.y);

        readAttribute<Imf::IntAttribute>(header, kSpp, image.meta.spp);
        readAttribute<Imf::IntAttribute>(header, kSeed, image.meta.seed);
        readAttribute<Imf::IntAttribute>(header, kSampleOffset, image.meta.sampleOffset);
        readAttribute<Imf::StringAttribute>(header, kIntegrator, image.meta.integrator);
        readAttribute<Imf::DoubleAttribute>(header, kRenderSeconds, image.meta.renderSeconds);
        readAttribute<Imf::StringAttribute>(header, kSampler, image.meta.sampler);
        if (const auto* pieces = header.findTypedAttribute<Imf::StringAttribute>(kPieces)) {
            try {
                image.meta.pieces = parseSamplePieces(pieces->value());
            } catch (const std::invalid_argument& e) {
                throwInputError(name, "", std::string(kPieces) + ": " + e.what());
            }
        }
        return image;
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throwInputError(name, "", "image too large to load");
    } catch (const std::exception& e) {
        // Iex exceptions (truncated or corrupt data, unreadable file) derive from std::exception.
        throwInputError(name, "", "cannot read OpenEXR image: " + oneLine(e.what()));
    }
}

}  // namespace

void writeExr(const std::filesystem::path& path, const Image& image) {
    if (image.width == 0 || image.height == 0 || image.width > INT32_MAX || image.height > INT32_MAX)
        throw std::runtime_error("failed to write " + path.string() + ": invalid image size " +
                                 std::to_string(image.width) + "x" + std::to_string(image.height));
    if (image.rgb.size() != size_t(image.width) * image.height * 3)
        throw std::runtime_error("failed to write " + path.string() + ": pixel buffer does not match the image size");

    // Encoded in memory first, so that the bytes can go to a regular file atomically or
    // through to a device or FIFO, where OpenEXR could not seek back to its offset table.
    MemoryOStream stream;
    try {
        Imf::Header header(int(image.width), int(image.height));
        header.compression() = Imf::ZIP_COMPRESSION;  // lossless; float noise compresses poorly with anything
        for (const char* c : kChannels) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        const ImageMetadata& m = image.meta;
        if (m.spp) header.insert(kSpp, Imf::IntAttribute(*m.spp));
        if (m.seed) header.insert(kSeed, Imf::IntAttribute(*m.seed));
        if (m.sampleOffset) header.insert(kSampleOffset, Imf::IntAttribute(*m.sampleOffset));
        if (m.integrator) header.insert(kIntegrator, Imf::StringAttribute(*m.integrator));
        if (m.renderSeconds) header.insert(kRenderSeconds, Imf::DoubleAttribute(*m.renderSeconds));
        if (m.sampler) header.insert(kSampler, Imf::StringAttribute(*m.sampler));
        if (m.pieces) header.insert(kPieces, Imf::StringAttribute(formatSamplePieces(*m.pieces)));

        Imf::FrameBuffer frame;
        const size_t xStride = 3 * sizeof(float), yStride = xStride * image.width;
        char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
        for (int c = 0; c < 3; ++c)
            frame.insert(kChannels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xStride, yStride));

        // The file is finished (offset table written) when OutputFile is destroyed.
        Imf::OutputFile file(stream, header);
        file.setFrameBuffer(frame);
        file.writePixels(int(image.height));
    } catch (const std::exception& e) {
        throw std::runtime_error("failed to write " + path.string() + ": " + oneLine(e.what()));
    }
    writeOutputFile(path, stream.bytes());
}

Image readExr(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throwInputError(name, "", "no such file");
    if (std::filesystem::is_directory(path, ec)) throwInputError(name, "", "is a directory, not an image");
    std::ifstream file(path, std::ios::binary);
    if (!file) throwInputError(name, "", std::string("cannot open: ") + std::strerror(errno));
    file.seekg(0, std::ios::end);
    const int64_t fileSize = file.tellg();
    file.seekg(0);
    Imf::StdIFStream stream(file, name.c_str());
    return readExrStream(stream, fileSize, name);
}

Image decodeExr(std::string_view bytes, const std::string& name) {
    MemoryIStream stream(bytes, name);
    return readExrStream(stream, int64_t(bytes.size()), name);
}

Image decodeExrRgba(std::string_view bytes, const std::string& name, std::vector<float>& rgba,
                    const std::function<void(uint32_t, uint32_t)>& acceptSize) {
    MemoryIStream stream(bytes, name);
    const RgbaTarget target{rgba, acceptSize};
    return readExrStream(stream, int64_t(bytes.size()), name, &target);
}

}  // namespace penumbra
