// core/image/image_io.cpp: OpenEXR 3.1 and stb_image_write.
// OpenEXR 3.1 allocates an attribute's declared size, and a chunk table of the declared length, before reading
// them: the header is walked here first (prescan_exr), which bounds every such allocation by the file's size.
// Guarding it keeps the Debian package; the C core API's limits would mean rewriting the reader for the same end.
#include "core/image/image_io.h"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <fcntl.h>
#include <stb_image_write.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/image/exr_io.h"

namespace pv {
namespace {

// An OpenEXR output stream on a file descriptor: buffered, positioned writes (pwrite), every one checked. The
// first failure is kept: OutputFile's destructor writes the line-offset table and swallows exceptions, so
// failed() is asked after it has run.
class FdOStream : public Imf::OStream {
public:
    FdOStream(int fd, const std::string& path) : Imf::OStream(path.c_str()), m_fd(fd), m_path(path) {}
    void write(const char c[], int n) override {
        if (m_buf.empty())
            m_buf_start = m_pos;
        else if (m_buf_start + m_buf.size() != m_pos) {
            flush();
            m_buf_start = m_pos;
        }
        m_buf.insert(m_buf.end(), c, c + n);
        m_pos += uint64_t(n);
        if (m_buf.size() >= (size_t(1) << 20)) flush();
    }
    uint64_t tellp() override { return m_pos; }
    void seekp(uint64_t pos) override {
        flush();
        m_pos = pos;
    }
    // Writes what is buffered; throws (and remembers) the first failure.
    void flush() {
        if (!m_error.empty()) throw Error(m_error);
        size_t done = 0;
        while (done < m_buf.size()) {
            const ssize_t n = ::pwrite(m_fd, m_buf.data() + done, m_buf.size() - done, off_t(m_buf_start + done));
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                m_error = m_path + ": cannot write: " + std::strerror(n < 0 ? errno : ENOSPC);
                throw Error(m_error);
            }
            done += size_t(n);
        }
        m_buf_start += m_buf.size();
        m_buf.clear();
    }
    const std::string& error() const { return m_error; }

private:
    int m_fd;
    std::string m_path, m_error;
    std::vector<char> m_buf;
    uint64_t m_pos = 0, m_buf_start = 0;
};

}  // namespace

namespace {
std::atomic<uint64_t> g_max_pixels{ImageLimits{}.max_pixels};
}

ImageLimits image_limits() { return ImageLimits{g_max_pixels.load(std::memory_order_relaxed)}; }
void set_image_limits(const ImageLimits& limits) { g_max_pixels.store(limits.max_pixels, std::memory_order_relaxed); }

float linear_to_srgb(float x) {
    x = glm::clamp(x, 0.f, 1.f);
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.f / 2.4f) - 0.055f;
}

void write_exr_atomically(const std::string& path, const Imf::Header& header,
                          const std::function<void(Imf::OutputFile&)>& fill) {
    write_file_atomically(path, [&](int fd) {
        FdOStream stream(fd, path);
        try {
            Imf::OutputFile file(stream, header);
            fill(file);
        } catch (const std::exception& e) {
            throw Error(stream.error().empty() ? path + ": cannot write EXR: " + e.what() : stream.error());
        }
        stream.flush();  // after ~OutputFile wrote the offset table (a failure there is kept, not lost)
    });
}

void write_exr(const std::string& path, const Image& image, const Metadata& metadata) {
    Imf::Header header(image.width, image.height);
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const auto& [k, v] : metadata) header.insert(k, Imf::StringAttribute(v));
    write_exr_atomically(path, header, [&](Imf::OutputFile& file) {
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * size_t(image.width);
        char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
        fb.insert("R", Imf::Slice(Imf::FLOAT, base, xs, ys));
        fb.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xs, ys));
        fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
        file.setFrameBuffer(fb);
        file.writePixels(image.height);
    });
}

namespace {

// An OpenEXR input stream on a descriptor (opened by read checks: regular files only), buffered pread.
class FdIStream : public Imf::IStream {
public:
    FdIStream(int fd, const std::string& path, uint64_t size) : Imf::IStream(path.c_str()), m_fd(fd), m_size(size) {}
    bool read(char c[], int n) override {
        // OpenEXR seeks to offsets read from the file: m_pos may be anything, so no m_pos + n (it can wrap).
        if (n < 0 || m_pos > m_size || uint64_t(n) > m_size - m_pos) throw Iex::InputExc("unexpected end of file");
        while (n > 0) {
            if (m_pos < m_buf_start || m_pos >= m_buf_start + m_buf.size()) fill();
            const size_t off = size_t(m_pos - m_buf_start);
            const size_t k = std::min(size_t(n), m_buf.size() - off);
            std::memcpy(c, m_buf.data() + off, k);
            c += k;
            n -= int(k);
            m_pos += k;
        }
        return m_pos < m_size;
    }
    uint64_t tellg() override { return m_pos; }
    void seekg(uint64_t pos) override { m_pos = pos; }

private:
    void fill() {
        m_buf.resize(size_t(std::min<uint64_t>(size_t(1) << 16, m_size - m_pos)));
        m_buf_start = m_pos;
        size_t done = 0;
        while (done < m_buf.size()) {
            const ssize_t r = ::pread(m_fd, m_buf.data() + done, m_buf.size() - done, off_t(m_pos + done));
            if (r < 0 && errno == EINTR) continue;
            if (r <= 0) throw Iex::InputExc(r < 0 ? std::strerror(errno) : "unexpected end of file");
            done += size_t(r);
        }
    }
    int m_fd;
    uint64_t m_size, m_pos = 0, m_buf_start = 0;
    std::vector<char> m_buf;
};

int32_t le32(const unsigned char* p) {
    return int32_t(uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24);
}

// What the EXR header declares, found by walking its attributes before OpenEXR does: OpenEXR allocates an
// attribute's declared size, and an offset table for the declared number of chunks, before reading them, so a
// 600-byte file can make it allocate gigabytes. Every attribute must fit in the file; the data window must fit
// the pixel budget and be plausible for the file's size. Throws pv::Error naming the file.
void prescan_exr(const std::string& path, const std::string& head, uint64_t file_size) {
    const auto* p = reinterpret_cast<const unsigned char*>(head.data());
    const size_t n = head.size();
    if (n < 8 || le32(p) != 20000630) throw Error(path + ": not an OpenEXR file (no EXR magic number)");
    const uint32_t version = uint32_t(le32(p + 4));
    if ((version & 0xff) != 2) throw Error(path + ": unsupported OpenEXR version " + std::to_string(version & 0xff));
    const bool multipart = version & 0x1000, long_names = version & 0x400;
    const size_t max_name = long_names ? 255 : 31;
    size_t pos = 8;
    auto string_at = [&](std::string& out) {
        const size_t end = head.find('\0', pos);
        if (end == std::string::npos || end - pos > max_name) return false;
        out = head.substr(pos, end - pos);
        pos = end + 1;
        return true;
    };
    bool have_window = false;
    int64_t w = 0, h = 0;
    for (int part = 0;; ++part) {
        if (pos < n && p[pos] == 0 && (part > 0 || !multipart)) break;  // the empty header ends the list
        for (;;) {
            std::string name, type;
            if (!string_at(name)) throw Error(path + ": corrupt EXR header (attribute name)");
            if (name.empty()) break;
            if (!string_at(type) || pos + 4 > n) throw Error(path + ": corrupt EXR header (attribute '" + name + "')");
            const int64_t size = le32(p + pos);
            pos += 4;
            if (size < 0 || uint64_t(pos) + uint64_t(size) > file_size)
                throw Error(path + ": corrupt EXR header: attribute '" + name + "' declares " + std::to_string(size) +
                            " bytes; the file has " + std::to_string(file_size));
            if (pos + size_t(size) > n) throw Error(path + ": EXR header larger than " + std::to_string(n) + " bytes");
            const unsigned char* v = p + pos;
            if (!have_window && name == "dataWindow" && type == "box2i" && size == 16) {
                w = int64_t(le32(v + 8)) - le32(v) + 1;
                h = int64_t(le32(v + 12)) - le32(v + 4) + 1;
                have_window = true;
            }
            if (name == "chunkCount" && type == "int" && size == 4 &&
                (le32(v) < 0 || uint64_t(le32(v)) * 8 > file_size))
                throw Error(path + ": corrupt EXR header: " + std::to_string(le32(v)) + " chunks in a file of " +
                            std::to_string(file_size) + " bytes");
            if (name == "tiles" && type == "tiledesc" && size == 9 &&
                (le32(v) <= 0 || le32(v + 4) <= 0 || int64_t(le32(v)) * le32(v + 4) > (int64_t(1) << 24)))
                throw Error(path + ": EXR tile size " + std::to_string(uint32_t(le32(v))) + "x" +
                            std::to_string(uint32_t(le32(v + 4))) + " is out of range");
            pos += size_t(size);
        }
        if (!multipart) break;
    }
    if (!have_window) throw Error(path + ": corrupt EXR header (no dataWindow)");
    if (w <= 0 || h <= 0) throw Error(path + ": EXR data window is empty");
    check_declared_size(path, w, h, file_size, kExrPixelsPerByte);
}

}  // namespace

void check_declared_size(const std::string& path, int64_t w, int64_t h, uint64_t file_size, double pixels_per_byte) {
    const uint64_t max_pixels = image_limits().max_pixels;
    const double pixels = double(w) * double(h);
    char buf[512];
    if (w <= 0 || h <= 0 || pixels > double(max_pixels)) {
        std::snprintf(buf, sizeof buf,
                      ": the image declares %lldx%lld pixels (%.1f megapixels); the limit is %.1f megapixels "
                      "(raise it with --max-image-megapixels)",
                      static_cast<long long>(w), static_cast<long long>(h), pixels * 1e-6, double(max_pixels) * 1e-6);
        throw Error(path + buf);
    }
    // Slack for headers, palettes and tiny images.
    if (pixels > double(file_size) * pixels_per_byte + 65536.0) {
        std::snprintf(buf, sizeof buf,
                      ": the image declares %lldx%lld pixels but the file has only %llu bytes, far too few for that "
                      "size in this format; truncated or corrupt",
                      static_cast<long long>(w), static_cast<long long>(h), static_cast<unsigned long long>(file_size));
        throw Error(path + buf);
    }
}

namespace {

// An OpenEXR input stream over bytes in memory (the fuzzer's and tests' path).
class MemIStream : public Imf::IStream {
public:
    MemIStream(const std::string& bytes, const std::string& name) : Imf::IStream(name.c_str()), m_bytes(bytes) {}
    bool read(char c[], int n) override {
        // OpenEXR seeks to offsets read from the file: m_pos may be anything, so no m_pos + n (it can wrap).
        if (n < 0 || m_pos > m_bytes.size() || uint64_t(n) > m_bytes.size() - m_pos)
            throw Iex::InputExc("unexpected end of file");
        std::memcpy(c, m_bytes.data() + m_pos, size_t(n));
        m_pos += uint64_t(n);
        return m_pos < m_bytes.size();
    }
    uint64_t tellg() override { return m_pos; }
    void seekg(uint64_t pos) override { m_pos = pos; }

private:
    const std::string& m_bytes;
    uint64_t m_pos = 0;
};

template <class Fn>
void read_exr_stream(const std::string& path, Imf::IStream& stream, Fn&& fn) {
    try {
        Imf::InputFile file(stream);
        fn(file);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR: " + e.what());
    }
}

// Opens an EXR for OpenEXR after the header walk; `fn` gets the Imf::InputFile.
template <class Fn>
void with_exr(const std::string& path, Fn&& fn, const char* what = "an EXR image") {
    const uint64_t size = regular_file_size(path, what);
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw Error(path + ": cannot open for reading: " + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) throw Error(path + ": not a regular file; expected " + what);
    // The header: the first 16 MiB at most (real headers, previews included, are far smaller).
    std::string head(size_t(std::min<uint64_t>(size, uint64_t(1) << 24)), '\0');
    size_t done = 0;
    while (done < head.size()) {
        const ssize_t r = ::pread(fd, head.data() + done, head.size() - done, off_t(done));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) throw Error(path + ": read error");
        done += size_t(r);
    }
    prescan_exr(path, head, size);
    head = std::string();
    FdIStream stream(fd, path, size);
    read_exr_stream(path, stream, fn);
}

// The data window's size, checked against the budget.
void window_size(const std::string& path, Imf::InputFile& file, long& w, long& h) {
    const Imath::Box2i dw = file.header().dataWindow();
    w = long(dw.max.x) - dw.min.x + 1;
    h = long(dw.max.y) - dw.min.y + 1;
    check_declared_size(path, w, h, ~uint64_t(0) >> 8, kExrPixelsPerByte);
}

// Reads R, G, B as FLOAT into the pixels at `data`, `xs` bytes apart, row after row of the data window.
void read_rgb(const std::string& path, Imf::InputFile& file, char* data, size_t xs) {
    const Imath::Box2i dw = file.header().dataWindow();
    const size_t ys = xs * (size_t(int64_t(dw.max.x) - dw.min.x) + 1);
    Imf::FrameBuffer fb;
    const char* names[] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        if (!file.header().channels().findChannel(names[c])) throw Error(path + ": EXR has no channel " + names[c]);
        // Slice::Make offsets the pointer by the window's origin in integer arithmetic: "data - origin" in pointer
        // arithmetic overflows for a negative origin (UBSan, found by fuzz_image).
        fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, data + c * sizeof(float), dw, xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
}

// Reads R, G, B into RGBA texels (alpha 1).
std::vector<vec4> read_rgba(const std::string& path, Imf::InputFile& file, int& width, int& height) {
    long w = 0, h = 0;
    window_size(path, file, w, h);
    std::vector<vec4> texels(size_t(w) * size_t(h), vec4(0.f, 0.f, 0.f, 1.f));
    read_rgb(path, file, reinterpret_cast<char*>(texels.data()), sizeof(vec4));
    width = int(w);
    height = int(h);
    return texels;
}

}  // namespace

void read_exr_guarded(const std::string& path, const std::function<void(Imf::InputFile&)>& read, const char* what) {
    with_exr(path, read, what);
}

Image read_exr(const std::string& path, Metadata* metadata) {
    Image img;
    with_exr(path, [&](Imf::InputFile& file) {
        long w = 0, h = 0;
        window_size(path, file, w, h);
        img = Image{int(w), int(h)};
        read_rgb(path, file, reinterpret_cast<char*>(img.rgb.data()), 3 * sizeof(float));
        if (metadata)
            for (auto it = file.header().begin(); it != file.header().end(); ++it)
                if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                    (*metadata)[it.name()] = s->value();
    });
    return img;
}

std::vector<vec4> read_exr_rgba(const std::string& path, int& width, int& height) {
    std::vector<vec4> texels;
    with_exr(path, [&](Imf::InputFile& file) { texels = read_rgba(path, file, width, height); });
    return texels;
}

std::vector<vec4> decode_exr_rgba(const std::string& bytes, const std::string& name, int& width, int& height) {
    prescan_exr(name, bytes.substr(0, size_t(1) << 24), bytes.size());
    MemIStream stream(bytes, name);
    std::vector<vec4> texels;
    read_exr_stream(name, stream, [&](Imf::InputFile& file) { texels = read_rgba(name, file, width, height); });
    return texels;
}

void write_png(const std::string& path, const Image& image, const DisplayTransform& transform) {
    write_png_bytes(path, image.width, image.height, display_bytes(image, transform));
}

void write_png_bytes(const std::string& path, int width, int height, const std::vector<uint8_t>& px) {
    // stb's file writer ignores write errors: encode to memory, then write with checked writes.
    std::vector<uint8_t> png;
    auto append = [](void* ctx, void* data, int size) {
        auto* out = static_cast<std::vector<uint8_t>*>(ctx);
        out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
    };
    if (!stbi_write_png_to_func(append, &png, width, height, 3, px.data(), width * 3))
        throw Error(path + ": cannot encode PNG (out of memory?)");
    write_file_atomically(path, [&](int fd) { write_all(fd, png.data(), png.size(), path); });
}

void write_image(const std::string& path, const Image& image, const Metadata& metadata,
                 const DisplayTransform& transform) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".exr" || ext == ".EXR") return write_exr(path, image, metadata);
    if (ext == ".png" || ext == ".PNG") return write_png(path, image, transform);
    throw Error(path + ": unknown image format '" + ext + "'; expected .exr or .png");
}

}  // namespace pv
