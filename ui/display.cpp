// ui/display.cpp: GL objects of the display pass. GL entry points come from GL_GLEXT_PROTOTYPES with Mesa's
// libGL (no loader); a core profile needs a VAO bound even for an attribute-less draw.
#include "display.h"

#include <GLFW/glfw3.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/base/error.h"

namespace pv::ui {
namespace {

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot read the shader (set by PATHVIEW_SHADERS); expected a GLSL file");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

unsigned compile(GLenum type, const std::string& source, const char* name) {
    const unsigned shader = glCreateShader(type);
    const char* src = source.c_str();
    glShaderSource(shader, 1, &src, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw Error(std::string(name) + ": GLSL compile error: " + log);
    }
    return shader;
}

unsigned make_texture() {
    unsigned tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

// Reallocates `tex` at w x h when the size changed, then replaces its texels.
void upload_texture(unsigned tex, bool realloc, GLint internal, GLenum format, int w, int h, const float* data) {
    glBindTexture(GL_TEXTURE_2D, tex);
    if (realloc) glTexImage2D(GL_TEXTURE_2D, 0, internal, w, h, 0, format, GL_FLOAT, nullptr);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, format, GL_FLOAT, data);
}

}  // namespace

void display_shader_sources(std::string& vert, std::string& frag) {
    if (const char* dir = std::getenv("PATHVIEW_SHADERS"); dir && *dir) {
        vert = read_text(std::string(dir) + "/display.vert");
        frag = read_text(std::string(dir) + "/display.frag");
    } else {
        vert = kEmbeddedDisplayVert;
        frag = kEmbeddedDisplayFrag;
    }
}

DisplayPass::DisplayPass() {
    std::string vert, frag;
    display_shader_sources(vert, frag);
    const unsigned vs = compile(GL_VERTEX_SHADER, vert, "display.vert");
    unsigned fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, frag, "display.frag");
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    m_program = glCreateProgram();
    glAttachShader(m_program, vs);
    glAttachShader(m_program, fs);
    glLinkProgram(m_program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(m_program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetProgramInfoLog(m_program, sizeof log, nullptr, log);
        glDeleteProgram(m_program);
        throw Error(std::string("display shaders: GLSL link error: ") + log);
    }
    glUseProgram(m_program);
    glUniform1i(glGetUniformLocation(m_program, "u_color"), 0);
    glUniform1i(glGetUniformLocation(m_program, "u_error"), 1);
    glUniform1i(glGetUniformLocation(m_program, "u_samples"), 2);
    glUniform1i(glGetUniformLocation(m_program, "u_b"), 3);
    glUniform1i(glGetUniformLocation(m_program, "u_diff"), 4);
    glUniform1i(glGetUniformLocation(m_program, "u_lut"), 5);
    m_loc_exposure = glGetUniformLocation(m_program, "u_exposure");
    m_loc_tone_map = glGetUniformLocation(m_program, "u_tone_map");
    m_loc_view = glGetUniformLocation(m_program, "u_view");
    m_loc_samples_max = glGetUniformLocation(m_program, "u_samples_max");
    m_loc_compare = glGetUniformLocation(m_program, "u_compare");
    m_loc_divider = glGetUniformLocation(m_program, "u_divider");
    m_loc_lut_size = glGetUniformLocation(m_program, "u_lut_size");
    m_loc_lut_log2 = glGetUniformLocation(m_program, "u_lut_log2");
    glUseProgram(0);
    glGenVertexArrays(1, &m_vao);
    m_tex_color = make_texture();
    m_tex_error = make_texture();
    m_tex_samples = make_texture();
    m_tex_display = make_texture();
    m_tex_b = make_texture();
    m_tex_diff = make_texture();
    glGenFramebuffers(1, &m_fbo);
    glGenTextures(1, &m_tex_lut);
    glBindTexture(GL_TEXTURE_3D, m_tex_lut);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTexParameteri(GL_TEXTURE_3D, wrap, GL_CLAMP_TO_EDGE);
    const float black[3] = {0.f, 0.f, 0.f};  // until a view is baked
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGB32F, 1, 1, 1, 0, GL_RGB, GL_FLOAT, black);
    glBindTexture(GL_TEXTURE_3D, 0);
}

DisplayPass::~DisplayPass() {
    const unsigned textures[] = {m_tex_color, m_tex_error, m_tex_samples, m_tex_display,
                                 m_tex_b,     m_tex_diff,  m_tex_lut};
    glDeleteTextures(7, textures);
    glDeleteFramebuffers(1, &m_fbo);
    glDeleteVertexArrays(1, &m_vao);
    glDeleteProgram(m_program);
}

void DisplayPass::upload(const Snapshot& s, bool denoised) {
    if (s.width <= 0 || s.height <= 0) return;
    const bool realloc = s.width != m_width || s.height != m_height;
    // Rows of 3 or 1 floats are multiples of 4 bytes: the default unpack alignment fits.
    const bool use_denoised = denoised && s.denoised.size() == s.rgb.size();
    upload_texture(m_tex_color, realloc, GL_RGB32F, GL_RGB, s.width, s.height,
                   use_denoised ? s.denoised.data() : s.rgb.data());
    upload_texture(m_tex_error, realloc, GL_R32F, GL_RED, s.width, s.height, s.rel_error.data());
    upload_texture(m_tex_samples, realloc, GL_R32F, GL_RED, s.width, s.height, s.samples.data());
    if (realloc) {
        glBindTexture(GL_TEXTURE_2D, m_tex_display);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, s.width, s.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m_tex_display, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    m_shaded = false;
    m_width = s.width;
    m_height = s.height;
    m_samples_max = static_cast<float>(std::max<uint32_t>(s.spp, 1));
}

void DisplayPass::upload_b(const Image& b) {
    if (b.width <= 0 || b.height <= 0 || b.rgb.size() != size_t(b.width) * size_t(b.height) * 3) return;
    upload_texture(m_tex_b, b.width != m_b_w || b.height != m_b_h, GL_RGB32F, GL_RGB, b.width, b.height, b.rgb.data());
    m_b_w = b.width;
    m_b_h = b.height;
    m_shaded = false;
}

void DisplayPass::upload_difference(const std::vector<float>& diff, int w, int h) {
    if (w <= 0 || h <= 0 || diff.size() != size_t(w) * size_t(h)) return;
    upload_texture(m_tex_diff, w != m_diff_w || h != m_diff_h, GL_R32F, GL_RED, w, h, diff.data());
    m_diff_w = w;
    m_diff_h = h;
    m_shaded = false;
}

void DisplayPass::upload_lut(const DisplayParams& p) {
    if (p.transform != ViewTransform::Ocio || !p.ocio || p.ocio == m_lut_view) return;
    const std::vector<float> lut = bake_display_lut(*p.ocio, kDisplayLutSize);
    glBindTexture(GL_TEXTURE_3D, m_tex_lut);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGB32F, kDisplayLutSize, kDisplayLutSize, kDisplayLutSize, 0, GL_RGB, GL_FLOAT,
                 lut.data());
    glBindTexture(GL_TEXTURE_3D, 0);
    m_lut_view = p.ocio;
}

void DisplayPass::shade(const DisplayParams& p) {
    if (m_shaded && p == m_shaded_params) return;
    upload_lut(p);
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    glViewport(0, 0, m_width, m_height);
    glUseProgram(m_program);
    glUniform1f(m_loc_exposure, p.exposure);
    // OpenColorIO without a view (none chosen yet) shows clamp.
    const ViewTransform t = p.transform == ViewTransform::Ocio && !p.ocio ? ViewTransform::Clamp : p.transform;
    glUniform1i(m_loc_tone_map, static_cast<int>(t));
    glUniform1f(m_loc_lut_size, float(kDisplayLutSize));
    glUniform2f(m_loc_lut_log2, kLutLog2Min, kLutLog2Max);
    glUniform1i(m_loc_view, static_cast<int>(p.view));
    glUniform1f(m_loc_samples_max, m_samples_max);
    // A compare view without its texture shows A.
    const bool b_ready = m_b_w > 0, diff_ready = m_diff_w > 0;
    const CompareView cv =
        (p.compare == CompareView::Difference && !diff_ready) || (p.compare != CompareView::Difference && !b_ready)
            ? CompareView::Off
            : p.compare;
    glUniform1i(m_loc_compare, static_cast<int>(cv));
    glUniform1f(m_loc_divider, p.divider);
    const unsigned textures[] = {m_tex_color, m_tex_error, m_tex_samples, m_tex_b, m_tex_diff};
    for (int i = 0; i < 5; ++i) {
        glActiveTexture(GL_TEXTURE0 + i);
        glBindTexture(GL_TEXTURE_2D, textures[i]);
    }
    glActiveTexture(GL_TEXTURE5);
    glBindTexture(GL_TEXTURE_3D, m_tex_lut);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(m_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    m_shaded = true;
    m_shaded_params = p;
}

void DisplayPass::clear(int fb_w, int fb_h) {
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.08f, 0.08f, 0.08f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
}

void DisplayPass::draw(int x, int y, int w, int h, const DisplayParams& p) {
    if (!has_image() || w <= 0 || h <= 0) return;
    shade(p);
    // Scale it into the image region (rows are bottom-up in both).
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, m_width, m_height, x, y, x + w, y + h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

std::vector<uint8_t> DisplayPass::read_shaded(const DisplayParams& p) {
    if (!has_image()) return {};
    shade(p);
    std::vector<uint8_t> rgba(size_t(m_width) * size_t(m_height) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, m_width, m_height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    // glReadPixels starts at the bottom row, which holds the image's bottom (the shader flips t); a PNG starts at the
    // top.
    std::vector<uint8_t> rgb(size_t(m_width) * size_t(m_height) * 3);
    for (int y = 0; y < m_height; ++y)
        for (int x = 0; x < m_width; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(size_t(y) * m_width + x) * 3 + c] = rgba[(size_t(m_height - 1 - y) * m_width + x) * 4 + c];
    return rgb;
}

}  // namespace pv::ui
