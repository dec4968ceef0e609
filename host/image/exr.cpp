// OpenEXR input and output of Penumbra images: R, G, B as 32-bit float, the AOV layers
// that penumbra:aovs names, and the penumbra:* header attributes of SCENE_FORMAT.md. Reading accepts any pixel type and
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
#include <OpenEXR/openexr.h>

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
#include "core/input_file.h"
#include "core/stop_request.h"
#include "image/aov_channels.h"
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
constexpr const char* kAovs = "penumbra:aovs";
constexpr const char* kChannels[3] = {"R", "G", "B"};

// Far beyond any film we render, small enough that a corrupt header claiming a huge
// data window is refused before we try to allocate it; each side at most a film's (16384).
constexpr int64_t kMaxPixels = int64_t(1) << 28;
constexpr int64_t kMaxSide = 16384;

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

// The penumbra:* attributes of `header` into `meta`.
void readMetadata(const Imf::Header& header, const std::string& name, ImageMetadata& meta) {
    readAttribute<Imf::IntAttribute>(header, kSpp, meta.spp);
    readAttribute<Imf::IntAttribute>(header, kSeed, meta.seed);
    readAttribute<Imf::IntAttribute>(header, kSampleOffset, meta.sampleOffset);
    readAttribute<Imf::StringAttribute>(header, kIntegrator, meta.integrator);
    readAttribute<Imf::DoubleAttribute>(header, kRenderSeconds, meta.renderSeconds);
    readAttribute<Imf::StringAttribute>(header, kSampler, meta.sampler);
    if (const auto* pieces = header.findTypedAttribute<Imf::StringAttribute>(kPieces)) {
        try {
            meta.pieces = parseSamplePieces(pieces->value());
        } catch (const std::invalid_argument& e) {
            throwInputError(name, "", std::string(kPieces) + ": " + e.what());
        }
    }
}

// The layers penumbra:aovs names ("depth,shape_id"), their channels checked against the
// header; their pixels still empty. A file without the attribute has none (its other
// channels, if any, are not ours to interpret).
std::vector<AovLayer> aovLayersOf(const Imf::Header& header, const std::string& name) {
    std::vector<AovLayer> layers;
    const auto* attr = header.findTypedAttribute<Imf::StringAttribute>(kAovs);
    if (!attr) return layers;
    const std::string& list = attr->value();
    for (size_t start = 0; start <= list.size();) {
        const size_t comma = std::min(list.find(',', start), list.size());
        AovLayer layer;
        layer.name = list.substr(start, comma - start);
        start = comma + 1;
        layer.channels = aovChannels(layer.name);
        if (layer.channels.empty())
            throwInputError(name, "", std::string(kAovs) + ": \"" + layer.name + "\" is no AOV");
        for (const AovLayer& earlier : layers)
            if (earlier.name == layer.name)
                throwInputError(name, "", std::string(kAovs) + ": \"" + layer.name + "\" given twice");
        const Imf::PixelType type = aovHoldsIds(layer.name) ? Imf::UINT : Imf::FLOAT;
        for (const std::string& channel : layer.channels) {
            const Imf::Channel* c = header.channels().findChannel(channel);
            if (!c)
                throwInputError(name, "", "missing channel " + channel + " (penumbra:aovs names " + layer.name + ")");
            // Ids as floats (or floats as ids) would be read converted: silently other numbers.
            if (c->type != type)
                throwInputError(name, "",
                                "channel " + channel + " is " + (c->type == Imf::UINT ? "uint" : "half or float") +
                                    ", expected " + (type == Imf::UINT ? "uint" : "float"));
        }
        layers.push_back(std::move(layer));
    }
    return layers;
}

// The AOV layers' pixels into `frame`, read with the image's (its data window `dw`).
void insertAovSlices(std::vector<AovLayer>& layers, const Imath::Box2i& dw, Imf::FrameBuffer& frame) {
    const size_t width = size_t(int64_t(dw.max.x) - dw.min.x + 1),
                 pixels = width * size_t(int64_t(dw.max.y) - dw.min.y + 1);
    for (AovLayer& layer : layers) {
        if (aovHoldsIds(layer.name)) {
            layer.ids.assign(pixels, 0);
            frame.insert(layer.channels[0],
                         Imf::Slice::Make(Imf::UINT, layer.ids.data(), dw, sizeof(uint32_t), width * sizeof(uint32_t)));
            continue;
        }
        const size_t n = layer.channels.size();
        layer.floats.assign(pixels * n, 0.0f);
        for (size_t c = 0; c < n; ++c)
            frame.insert(layer.channels[c], Imf::Slice::Make(Imf::FLOAT, layer.floats.data() + c, dw, n * sizeof(float),
                                                             width * n * sizeof(float)));
    }
}

// Where decodeExrRgba puts the pixels, and who accepts their number first.
struct RgbaTarget {
    std::vector<float>& pixels;
    const std::function<void(uint32_t, uint32_t)>& acceptSize;
};

// Decompresses every chunk of a scanline image (part 0) with OpenEXR's core library, one
// chunk's memory at a time, and refuses the file at the first chunk that does not
// decompress to the size its header implies. The C++ reader does not check that: a 4 x
// 16384 render whose header claimed 16384 x 16384 was read as a 3 GiB image of garbage
// (exit 0, 94 s, 6 GB), where this finds the first chunk short before anything is
// allocated. Tiled files (which penumbra does not write) are left to the C++ reader.
void checkChunks(Imf::IStream& in, int64_t fileSize, const std::string& name) {
    struct Source {
        Imf::IStream& in;
        int64_t size;
    } source{in, fileSize};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &source;
    init.error_handler_fn = [](exr_const_context_t, exr_result_t, const char*) {};  // reported below
    init.size_fn = [](exr_const_context_t, void* user) { return static_cast<Source*>(user)->size; };
    init.read_fn = [](exr_const_context_t, void* user, void* buffer, uint64_t size, uint64_t offset,
                      exr_stream_error_func_ptr_t) -> int64_t {
        auto& src = *static_cast<Source*>(user);
        if (offset > uint64_t(src.size)) return -1;
        const uint64_t n = std::min(size, uint64_t(src.size) - offset);
        try {
            src.in.seekg(offset);
            src.in.read(static_cast<char*>(buffer), int(n));
        } catch (const std::exception&) {
            return -1;
        }
        return int64_t(n);
    };
    exr_context_t context = nullptr;
    auto fail = [&](exr_result_t result, const char* what) {
        exr_finish(&context);
        throwInputError(
            name, "", std::string("cannot read OpenEXR image: ") + what + ": " + exr_get_default_error_message(result));
    };
    exr_result_t result = exr_start_read(&context, name.c_str(), &init);
    if (result != EXR_ERR_SUCCESS) fail(result, "header");
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    exr_get_storage(context, 0, &storage);
    if (storage != EXR_STORAGE_SCANLINE) {
        exr_finish(&context);
        return;
    }
    exr_attr_box2i_t window;
    int32_t lines = 1;
    exr_get_data_window(context, 0, &window);
    exr_get_scanlines_per_chunk(context, 0, &lines);
    exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
    bool first = true;
    for (int64_t y = window.min.y; y <= window.max.y; y += std::max(lines, 1)) {
        exr_chunk_info_t chunk;
        result = exr_read_scanline_chunk_info(context, 0, int(y), &chunk);
        // No channel has a destination: the pipeline reads and decompresses only.
        if (result == EXR_ERR_SUCCESS)
            result = first ? exr_decoding_initialize(context, 0, &chunk, &decoder)
                           : exr_decoding_update(context, 0, &chunk, &decoder);
        if (result == EXR_ERR_SUCCESS && first) result = exr_decoding_choose_default_routines(context, 0, &decoder);
        first = false;
        if (result == EXR_ERR_SUCCESS) result = exr_decoding_run(context, 0, &decoder);
        if (result != EXR_ERR_SUCCESS) {
            exr_decoding_destroy(context, &decoder);
            fail(result, ("pixel data at line " + std::to_string(y)).c_str());
        }
    }
    exr_decoding_destroy(context, &decoder);
    exr_finish(&context);
}

// The image in `in` (a file or memory, fileSize bytes long), checked before OpenEXR
// allocates anything; InputErrors name `name`. With `rgba`, the pixels go there (4 floats
// a pixel, alpha 1) instead of image.rgb; with `headerOnly`, none is read (rgb empty).
Image readExrStream(Imf::IStream& in, int64_t fileSize, const std::string& name, const RgbaTarget* rgba = nullptr,
                    bool headerOnly = false) {
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
        if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide || width > kMaxPixels / height)
            throwInputError(name, "", "unsupported data window " + std::to_string(width) + "x" + std::to_string(height));

        Image image;
        image.width = uint32_t(width);
        image.height = uint32_t(height);
        readMetadata(header, name, image.meta);
        // An RGBA reader (a texture or an environment map) wants the colour alone.
        if (!rgba) image.aovs = aovLayersOf(header, name);
        if (headerOnly) return image;
        if (rgba) rgba->acceptSize(image.width, image.height);
        checkChunks(in, fileSize, name);
        float* pixels = nullptr;
        size_t stride = 3;  // floats a pixel
        if (rgba) {
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
        insertAovSlices(image.aovs, dw, frame);
        file.setFrameBuffer(frame);
        // In blocks of 256 scanlines (a multiple of every compression's lines per chunk, so
        // no chunk is decoded twice), so that a stop asked for meanwhile waits one block.
        for (int y = dw.min.y; y <= dw.max.y; y += 256) {
            throwIfStopRequested();
            file.readPixels(y, int(std::min<int64_t>(int64_t(y) + 255, dw.max.y)));
        }
        return image;
    } catch (const InputError&) {
        throw;
    } catch (const Stopped&) {
        throw;
    } catch (const std::bad_alloc&) {
        throwInputError(name, "", "image too large to load");
    } catch (const std::exception& e) {
        // Iex exceptions (truncated or corrupt data, unreadable file) derive from std::exception.
        throwInputError(name, "", "cannot read OpenEXR image: " + oneLine(e.what()));
    }
}

// readExr and readExrHeader: a file on disk, checked as in readExrStream.
Image readExrFile(const std::filesystem::path& path, bool headerOnly) {
    const std::string name = path.string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throwInputError(name, "", "no such file");
    if (std::filesystem::is_directory(path, ec)) throwInputError(name, "", "is a directory, not an image");
    checkRegularFile(path, name);  // a FIFO would block the open below
    std::ifstream file(path, std::ios::binary);
    if (!file) throwInputError(name, "", std::string("cannot open: ") + std::strerror(errno));
    file.seekg(0, std::ios::end);
    const int64_t fileSize = file.tellg();
    file.seekg(0);
    Imf::StdIFStream stream(file, name.c_str());
    return readExrStream(stream, fileSize, name, nullptr, headerOnly);
}

// The AOV layers' channels (float, or UINT for ids) and penumbra:aovs, their names.
void insertAovChannels(const Image& image, Imf::Header& header, Imf::FrameBuffer& frame) {
    if (image.aovs.empty()) return;
    std::string names;
    for (const AovLayer& layer : image.aovs) {
        names += (names.empty() ? "" : ",") + layer.name;
        const size_t pixels = size_t(image.width) * image.height;
        if (!layer.ids.empty()) {
            if (layer.ids.size() != pixels || layer.channels.size() != 1)
                throw std::runtime_error("AOV " + layer.name + " does not match the image size");
            header.channels().insert(layer.channels[0], Imf::Channel(Imf::UINT));
            char* base = reinterpret_cast<char*>(const_cast<uint32_t*>(layer.ids.data()));
            frame.insert(layer.channels[0],
                         Imf::Slice(Imf::UINT, base, sizeof(uint32_t), sizeof(uint32_t) * image.width));
            continue;
        }
        const size_t n = layer.channels.size();
        if (n == 0 || layer.floats.size() != pixels * n)
            throw std::runtime_error("AOV " + layer.name + " does not match the image size");
        char* base = reinterpret_cast<char*>(const_cast<float*>(layer.floats.data()));
        for (size_t c = 0; c < n; ++c) {
            header.channels().insert(layer.channels[c], Imf::Channel(Imf::FLOAT));
            frame.insert(layer.channels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), n * sizeof(float),
                                                       n * sizeof(float) * image.width));
        }
    }
    header.insert(kAovs, Imf::StringAttribute(names));
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
        insertAovChannels(image, header, frame);

        // The file is finished (offset table written) when OutputFile is destroyed.
        Imf::OutputFile file(stream, header);
        file.setFrameBuffer(frame);
        file.writePixels(int(image.height));
    } catch (const std::exception& e) {
        throw std::runtime_error("failed to write " + path.string() + ": " + oneLine(e.what()));
    }
    writeOutputFile(path, stream.bytes());
}

Image readExr(const std::filesystem::path& path) { return readExrFile(path, false); }
Image readExrHeader(const std::filesystem::path& path) { return readExrFile(path, true); }

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
