// core/image/ocio_view.h: an OpenColorIO 2.1 config and one of its display/view pairs, applied on the CPU to the
// film's linear RGB (handed to the config as its scene_linear role, or another colour space the user names). PNG
// output applies the processor itself; the viewer samples a 3D LUT baked from it (bake_display_lut) through a log2
// shaper, lut_coordinate, that shaders/display.frag repeats with the constants below as uniforms.
// OpenColorIO's types stay in ocio_view.cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/base/math.h"

namespace pv {

class OcioConfig {
public:
    // Reads the config at `path`, or the one $OCIO names when `path` is empty. Throws pv::Error naming the file and
    // what OpenColorIO found wrong (or that $OCIO is not set).
    static std::shared_ptr<const OcioConfig> load(const std::string& path);
    ~OcioConfig();
    const std::string& path() const;
    std::vector<std::string> displays() const;
    std::string default_display() const;
    std::vector<std::string> views(const std::string& display) const;
    std::string default_view(const std::string& display) const;

    struct Impl;
    explicit OcioConfig(std::unique_ptr<Impl> impl);
    const Impl& impl() const { return *m_impl; }

private:
    std::unique_ptr<Impl> m_impl;
};

// A display/view of a config as a CPU processor (its apply is const and thread-safe).
class OcioView {
public:
    // An empty display or view is the config's default (the display's default view). Throws pv::Error naming the
    // config and listing the choices for an unknown display, view or input colour space.
    OcioView(std::shared_ptr<const OcioConfig> config, const std::string& display, const std::string& view,
             const std::string& input = "scene_linear");
    ~OcioView();
    // Linear RGB (interleaved, `pixels` of them) to the display's code values, in place.
    void apply(float* rgb, size_t pixels) const;
    const std::string& display() const { return m_display; }
    const std::string& view() const { return m_view; }
    const std::string& input() const { return m_input; }
    const OcioConfig& config() const { return *m_config; }
    // "sRGB/Standard" (and " from INPUT" when the input is not scene_linear).
    std::string describe() const;

private:
    struct Processor;
    std::shared_ptr<const OcioConfig> m_config;
    std::string m_display, m_view, m_input;
    std::unique_ptr<Processor> m_processor;
};

// The viewer's LUT: kDisplayLutSize^3 RGB nodes. Node 0 of each axis is linear 0; node k >= 1 is
// 2^(kLutLog2Min + (k - 1) (kLutLog2Max - kLutLog2Min) / (size - 2)); between 0 and node 1 the coordinate is linear.
// 24 stops in 63 steps (0.38 stop); radiance above 2^10 is taken as 2^10 (every view's white has clipped by then).
constexpr int kDisplayLutSize = 65;
constexpr float kLutLog2Min = -14.f;
constexpr float kLutLog2Max = 10.f;
// The LUT coordinate of a linear value, in nodes: [0, size - 1].
float lut_coordinate(float linear, int size = kDisplayLutSize);
// The view's output at every node, red fastest (the layout of a GL 3D texture), RGB floats.
std::vector<float> bake_display_lut(const OcioView& view, int size = kDisplayLutSize);
// Trilinear interpolation of a baked LUT at linear `c`, as the GPU samples it (tests compare it with apply()).
vec3 sample_display_lut(const std::vector<float>& lut, int size, vec3 c);

}  // namespace pv
