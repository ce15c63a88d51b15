// core/image/ocio_view.cpp: OpenColorIO configs and display/view processors (see ocio_view.h).
#include "core/image/ocio_view.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/base/error.h"

namespace OCIO = OCIO_NAMESPACE;

namespace pv {

struct OcioConfig::Impl {
    std::string path;
    OCIO::ConstConfigRcPtr config;
};

struct OcioView::Processor {
    OCIO::ConstCPUProcessorRcPtr cpu;
};

namespace {

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "'" : ", '") + n + "'";
    return s.empty() ? "none" : s;
}

}  // namespace

OcioConfig::OcioConfig(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
OcioConfig::~OcioConfig() = default;

std::shared_ptr<const OcioConfig> OcioConfig::load(const std::string& path) {
    auto impl = std::make_unique<Impl>();
    impl->path = path;
    if (impl->path.empty()) {
        const char* env = std::getenv("OCIO");
        if (!env || !*env) throw Error("OpenColorIO: no config: give --ocio-config FILE or set $OCIO to a config.ocio");
        impl->path = env;
    }
    try {
        impl->config = OCIO::Config::CreateFromFile(impl->path.c_str());
        impl->config->validate();
    } catch (const OCIO::Exception& e) {
        throw Error(impl->path + ": not a usable OpenColorIO config: " + e.what());
    }
    if (impl->config->getNumDisplays() == 0)
        throw Error(impl->path + ": the OpenColorIO config has no display; expected at least one display and view");
    return std::make_shared<const OcioConfig>(std::move(impl));
}

const std::string& OcioConfig::path() const { return m_impl->path; }

std::vector<std::string> OcioConfig::displays() const {
    std::vector<std::string> out;
    for (int i = 0; i < m_impl->config->getNumDisplays(); ++i) out.emplace_back(m_impl->config->getDisplay(i));
    return out;
}

std::string OcioConfig::default_display() const { return m_impl->config->getDefaultDisplay(); }

std::vector<std::string> OcioConfig::views(const std::string& display) const {
    std::vector<std::string> out;
    for (int i = 0; i < m_impl->config->getNumViews(display.c_str()); ++i)
        out.emplace_back(m_impl->config->getView(display.c_str(), i));
    return out;
}

std::string OcioConfig::default_view(const std::string& display) const {
    return m_impl->config->getDefaultView(display.c_str());
}

OcioView::OcioView(std::shared_ptr<const OcioConfig> config, const std::string& display, const std::string& view,
                   const std::string& input)
    : m_config(std::move(config)), m_input(input) {
    const OcioConfig& c = *m_config;
    const std::vector<std::string> displays = c.displays();
    m_display = display.empty() ? c.default_display() : display;
    if (std::find(displays.begin(), displays.end(), m_display) == displays.end())
        throw Error(c.path() + ": no display '" + m_display + "' (--ocio-display); the config has " + joined(displays));
    const std::vector<std::string> views = c.views(m_display);
    m_view = view.empty() ? c.default_view(m_display) : view;
    if (std::find(views.begin(), views.end(), m_view) == views.end())
        throw Error(c.path() + ": display '" + m_display + "' has no view '" + m_view + "' (--ocio-view); it has " +
                    joined(views));
    const OCIO::ConstConfigRcPtr& cfg = c.impl().config;
    if (!cfg->getColorSpace(m_input.c_str()))
        throw Error(c.path() + ": no colour space or role '" + m_input +
                    "' (--ocio-input) for pathview's linear Rec.709 RGB; expected a scene_linear role or a "
                    "colour space name");
    try {
        auto t = OCIO::DisplayViewTransform::Create();
        t->setSrc(m_input.c_str());
        t->setDisplay(m_display.c_str());
        t->setView(m_view.c_str());
        m_processor = std::make_unique<Processor>();
        m_processor->cpu = cfg->getProcessor(t)->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        throw Error(c.path() + ": display '" + m_display + "', view '" + m_view + "': " + e.what());
    }
}

OcioView::~OcioView() = default;

void OcioView::apply(float* rgb, size_t pixels) const {
    if (!pixels) return;
    OCIO::PackedImageDesc image(rgb, long(pixels), 1, 3);
    m_processor->cpu->apply(image);
}

std::string OcioView::describe() const {
    return m_display + "/" + m_view + (m_input == "scene_linear" ? "" : " from " + m_input);
}

float lut_coordinate(float linear, int size) {
    const float first = std::exp2(kLutLog2Min);
    if (!(linear > 0.f)) return 0.f;
    if (linear < first) return linear / first;
    const float u = 1.f + (std::log2(linear) - kLutLog2Min) / (kLutLog2Max - kLutLog2Min) * float(size - 2);
    return std::min(u, float(size - 1));
}

std::vector<float> bake_display_lut(const OcioView& view, int size) {
    std::vector<float> node(size);
    node[0] = 0.f;
    for (int k = 1; k < size; ++k)
        node[k] = std::exp2(kLutLog2Min + float(k - 1) * (kLutLog2Max - kLutLog2Min) / float(size - 2));
    std::vector<float> lut(size_t(size) * size * size * 3);
    size_t i = 0;
    for (int b = 0; b < size; ++b)
        for (int g = 0; g < size; ++g)
            for (int r = 0; r < size; ++r) {
                lut[i++] = node[r];
                lut[i++] = node[g];
                lut[i++] = node[b];
            }
    view.apply(lut.data(), lut.size() / 3);
    return lut;
}

vec3 sample_display_lut(const std::vector<float>& lut, int size, vec3 c) {
    float u[3];
    int i0[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = lut_coordinate(c[k], size);
        i0[k] = std::min(int(u[k]), size - 2);
        u[k] -= float(i0[k]);
    }
    vec3 out(0.f);
    for (int corner = 0; corner < 8; ++corner) {
        float w = 1.f;
        size_t index = 0, stride = 1;
        for (int k = 0; k < 3; ++k) {
            const int bit = (corner >> k) & 1;
            w *= bit ? u[k] : 1.f - u[k];
            index += size_t(i0[k] + bit) * stride;
            stride *= size_t(size);
        }
        out += w * vec3(lut[index * 3], lut[index * 3 + 1], lut[index * 3 + 2]);
    }
    return out;
}

}  // namespace pv
