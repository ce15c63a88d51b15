// ui/compare.h: before/after comparison. The image shown (A, live) is compared with a held image B: one taken from
// the screen (key B, "Hold B") or read from an EXR (the panel's path field, `pathview view --compare FILE.exr`).
// Views: A alone, A | B split by a vertical divider (right drag moves it), B alone (V flips), and the relative
// difference |A - B| / (B + eps) in false colour. Window-free: the viewer feeds it snapshots.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "convergence.h"
#include "core/frame/progressive.h"
#include "core/image/film.h"

namespace pv::ui {

enum class CompareView : int { Off = 0, Split = 1, ShowB = 2, Difference = 3 };

// What the user asked of the comparison in one frame (keys, gestures, panel).
struct CompareActions {
    bool hold = false;                // hold the displayed image as B
    bool cycle = false;               // Off -> Split -> Difference -> Off
    bool flip = false;                // B alone <-> the view before
    std::optional<CompareView> view;  // set the view
    std::optional<float> divider;     // the divider at this fraction of the image width (split view)
    std::string load;                 // non-empty: read this EXR as B
    bool clear = false;               // forget B
};

// Against B the panel shows the live relMSE of A (core/image/metrics.h) and its history. The viewer uploads what
// Compare computes (ui/display.h).
class Compare {
public:
    // eps of the difference view, as core/image/metrics.h's relMSE and MAPE.
    static constexpr float kEps = 0.01f;

    // Applies a frame's actions. `displayed` is the image on screen (A), `denoised` whether its denoised image is
    // shown, `camera` the current camera, `full_w` x `full_h` the image region's full resolution (the size an EXR
    // must have). True when B or the view changed (the display needs new textures).
    bool apply(const CompareActions& a, const Snapshot& displayed, bool denoised, const CameraDesc& camera, int full_w,
               int full_h);

    // Holds the colour A shows now (the denoised image when shown and present) as B, with the camera it was seen
    // from. Nothing rendered yet: B stays as it was and the status says so.
    void hold(const Snapshot& displayed, bool denoised, const CameraDesc& camera);
    // Reads B from an EXR of exactly full_w x full_h pixels. On failure B stays as it was, status() names the file
    // and what is wrong, and false is returned.
    bool load(const std::string& path, int full_w, int full_h);
    // B from an image already read (the command line's --compare); `source` names it.
    void set_b(Image image, const std::string& source);
    void clear();

    // A new snapshot on screen: its relMSE against B when the sizes match (the raw mean, and the denoised image
    // when it has one), added to the history of the snapshot's accumulation.
    void update(const Snapshot& shown);

    bool has_b() const { return m_b.width > 0; }
    const Image& b() const { return m_b; }
    const std::string& source() const { return m_source; }  // "held at 16 spp" or the EXR's path
    bool from_file() const { return m_from_file; }
    // B was held from the screen and the camera has changed since (an EXR's camera is not known: false).
    bool camera_moved(const CameraDesc& now) const;

    CompareView view() const { return has_b() ? m_view : CompareView::Off; }
    float divider() const { return m_divider; }  // fraction of the image width; A left of it, B right

    // |A - B| / (B + eps), averaged over the three channels, at A's size (w x h, rgb rows from the top); B is
    // sampled at the nearest pixel when its size differs. Empty without B.
    std::vector<float> difference(const float* a_rgb, int w, int h) const;

    // relMSE of the shown accumulation's raw mean (and of its denoised image: < 0 when none) against B, from the
    // last update(); nothing when there is no B or the sizes differ (e.g. a 1/4-resolution pass).
    std::optional<double> rel_mse() const { return m_rel_mse; }
    double rel_mse_denoised() const { return m_rel_mse_denoised; }
    const ConvergenceHistory& history() const { return m_history; }

    const std::string& status() const { return m_status; }  // one line: what was held or loaded, or what failed
    bool ok() const { return m_ok; }

private:
    void set_view(CompareView v);

    Image m_b;
    std::string m_source;
    bool m_from_file = false;
    std::optional<CameraDesc> m_camera;  // where B was held from
    CompareView m_view = CompareView::Off;
    CompareView m_before_flip = CompareView::Off;
    float m_divider = 0.5f;
    std::optional<double> m_rel_mse;
    double m_rel_mse_denoised = -1.0;
    ConvergenceHistory m_history;
    uint64_t m_history_generation = 0;
    std::string m_status;
    bool m_ok = true;
};

const char* compare_view_name(CompareView v);

}  // namespace pv::ui
