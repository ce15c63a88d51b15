// ui/display.h: the display pass. The latest Snapshot lives in float textures (uploaded with glTexSubImage2D) and
// a fullscreen triangle runs shaders/display.frag (exposure, view transform and display encoding, or a false-colour
// view) into an 8-bit texture of the snapshot's size, only when the snapshot or the display parameters change;
// every frame then scales that texture into the image region with a linear blit. An OpenColorIO view is a 3D LUT
// baked on the CPU from its processor (core/image/ocio_view.h), sampled through the same log2 shaper.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "compare.h"
#include "core/frame/progressive.h"
#include "core/image/ocio_view.h"
#include "core/image/view_transform.h"

namespace pv::ui {

enum class View : int { Colour = 0, RelativeError = 1, SampleCount = 2 };

// What the display shows; changing it never restarts accumulation.
struct DisplayParams {
    float exposure = 0.f;                           // stops
    ViewTransform transform = ViewTransform::Aces;  // core/image/view_transform.h; shaders/display.frag's twin
    std::shared_ptr<const OcioView> ocio;           // with ViewTransform::Ocio: sampled as a baked 3D LUT
    View view = View::Colour;
    // Show the snapshot's a-trous denoised image (Snapshot::denoised) in the colour view when there is one (the
    // default, coarse passes included); off: the raw accumulation (key N). The viewer turns the driver's denoising
    // on and off with it; the accumulation and the error readouts are never touched.
    bool denoise = true;
    // The comparison with a held image B (compare.h); the viewer copies it from its Compare each frame.
    CompareView compare = CompareView::Off;
    float divider = 0.5f;  // split view: A left of this fraction of the width, B right of it
    bool operator==(const DisplayParams& o) const {
        return exposure == o.exposure && transform == o.transform && ocio == o.ocio && view == o.view &&
               denoise == o.denoise && compare == o.compare && divider == o.divider;
    }
    bool operator!=(const DisplayParams& o) const { return !(*this == o); }
};

// The shader sources: embedded at build time, or read from $PATHVIEW_SHADERS/display.{vert,frag} when that is set.
// Throws pv::Error naming the file when an override cannot be read.
void display_shader_sources(std::string& vert, std::string& frag);
extern const char* const kEmbeddedDisplayVert;
extern const char* const kEmbeddedDisplayFrag;

// Shading only on change, then blitting: on a software rasteriser this keeps frames that only redraw the panel
// cheap, and a 1/4-resolution preview costs 1/16 of the shading. Needs a current OpenGL 3.3 core context for its whole
// life.
class DisplayPass {
public:
    // Compiles and links the display program; throws pv::Error with the GLSL log on failure.
    DisplayPass();
    ~DisplayPass();
    DisplayPass(const DisplayPass&) = delete;
    DisplayPass& operator=(const DisplayPass&) = delete;

    // Copies the snapshot's images into the textures (reallocated when the size changes); the colour texture gets
    // the denoised image when `denoised` and the snapshot has one.
    void upload(const Snapshot& snapshot, bool denoised = false);
    // B of the compare views (any size: sampled by texture coordinates) and |A - B| / (B + eps) (Compare::difference).
    void upload_b(const Image& b);
    void upload_difference(const std::vector<float>& diff, int w, int h);
    // Clears the default framebuffer (fb_w x fb_h pixels) to the window's backdrop.
    static void clear(int fb_w, int fb_h);
    // Draws into the rectangle (x, y, w, h) of the default framebuffer, in pixels from the bottom-left.
    void draw(int x, int y, int w, int h, const DisplayParams& params);
    // The uploaded image shaded with `params`, read back: 8-bit RGB at the snapshot's size, row 0 at the top (what
    // a PNG of the same image through the same DisplayTransform holds, up to the GPU's rounding).
    std::vector<uint8_t> read_shaded(const DisplayParams& params);
    bool has_image() const { return m_width > 0; }

private:
    // Shades the snapshot at its own resolution into m_tex_display when it or `params` changed.
    void shade(const DisplayParams& params);
    // Bakes and uploads the LUT of params.ocio when it is not the one uploaded.
    void upload_lut(const DisplayParams& params);

    unsigned m_program = 0, m_vao = 0;
    unsigned m_tex_lut = 0;                      // GL_TEXTURE_3D, RGB32F, kDisplayLutSize^3
    std::shared_ptr<const OcioView> m_lut_view;  // the view baked into m_tex_lut
    unsigned m_tex_color = 0, m_tex_error = 0, m_tex_samples = 0, m_tex_b = 0, m_tex_diff = 0;
    int m_b_w = 0, m_b_h = 0, m_diff_w = 0, m_diff_h = 0;
    unsigned m_fbo = 0, m_tex_display = 0;  // the shaded image, RGBA8 at the snapshot's size
    bool m_shaded = false;                  // m_tex_display matches the textures and m_shaded_params
    DisplayParams m_shaded_params;
    int m_width = 0, m_height = 0;
    float m_samples_max = 1.f;
    int m_loc_exposure = -1, m_loc_tone_map = -1, m_loc_view = -1, m_loc_samples_max = -1;
    int m_loc_lut_size = -1, m_loc_lut_log2 = -1;
    int m_loc_compare = -1, m_loc_divider = -1;
};

}  // namespace pv::ui
