// core/image_io.cpp: OpenEXR 3.1 and stb_image_write.
#include "core/image_io.h"

#include "core/error.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <Iex.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <filesystem>

namespace pv {
namespace {

std::string temp_name(const std::string& path) {
    return path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
}

void commit(const std::string& tmp, const std::string& path) {
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw Error(path + ": cannot write: " + ec.message());
    }
}

void check_folder(const std::string& path) {
    const auto dir = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
        throw Error(path + ": cannot write: folder '" + dir.string() + "' does not exist");
}

}  // namespace

float linear_to_srgb(float x) {
    x = glm::clamp(x, 0.f, 1.f);
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.f / 2.4f) - 0.055f;
}

void write_exr(const std::string& path, const Image& image, const Metadata& metadata) {
    check_folder(path);
    const std::string tmp = temp_name(path);
    try {
        Imf::Header header(image.width, image.height);
        for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        for (const auto& [k, v] : metadata) header.insert(k, Imf::StringAttribute(v));
        Imf::OutputFile file(tmp.c_str(), header);
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * size_t(image.width);
        char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
        fb.insert("R", Imf::Slice(Imf::FLOAT, base, xs, ys));
        fb.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xs, ys));
        fb.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
        file.setFrameBuffer(fb);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw Error(path + ": cannot write EXR: " + e.what());
    }
    commit(tmp, path);
}

Image read_exr(const std::string& path, Metadata* metadata) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path + ": no such file; expected an EXR image");
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
        if (w <= 0 || h <= 0 || w * h > (1l << 28)) throw Error(path + ": EXR data window is empty or too large");
        Image img{int(w), int(h)};
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * size_t(w);
        char* base = reinterpret_cast<char*>(img.rgb.data()) - (size_t(dw.min.x) * xs + size_t(dw.min.y) * ys);
        const char* names[] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c) {
            if (!file.header().channels().findChannel(names[c])) throw Error(path + ": EXR has no channel " + names[c]);
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        if (metadata)
            for (auto it = file.header().begin(); it != file.header().end(); ++it)
                if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) (*metadata)[it.name()] = s->value();
        return img;
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR: " + e.what());
    }
}

void write_png(const std::string& path, const Image& image, float exposure) {
    check_folder(path);
    const float scale = std::exp2(exposure);
    std::vector<uint8_t> px(size_t(image.width) * size_t(image.height) * 3);
    for (size_t i = 0; i < px.size(); ++i)
        px[i] = static_cast<uint8_t>(glm::clamp(linear_to_srgb(image.rgb[i] * scale) * 255.f + 0.5f, 0.f, 255.f));
    const std::string tmp = temp_name(path);
    if (!stbi_write_png(tmp.c_str(), image.width, image.height, 3, px.data(), image.width * 3)) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw Error(path + ": cannot write PNG (permission denied or disk full?)");
    }
    commit(tmp, path);
}

void write_via_temporary(const std::string& path, const std::function<void(const std::string& tmp)>& write) {
    check_folder(path);
    const std::string tmp = temp_name(path);
    try {
        write(tmp);
    } catch (const std::exception& e) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw Error(path + ": cannot write: " + e.what());
    }
    commit(tmp, path);
}

void write_image(const std::string& path, const Image& image, const Metadata& metadata) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".exr" || ext == ".EXR") return write_exr(path, image, metadata);
    if (ext == ".png" || ext == ".PNG") return write_png(path, image);
    throw Error(path + ": unknown image format '" + ext + "'; expected .exr or .png");
}

}  // namespace pv
