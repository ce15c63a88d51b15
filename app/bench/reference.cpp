// app/bench/reference.cpp: the bench's reference (see reference.h).
#include "app/bench/reference.h"

#include <algorithm>
#include <cstdio>

#include "core/base/error.h"
#include "core/image/image_io.h"

namespace pv::app {

Reference make_reference(const BenchOptions& o, Renderer& renderer, const CameraDesc& camera, ProgressBar& progress) {
    Reference ref;
    if (!o.reference.empty()) {
        Metadata md;
        ref.image = read_exr(o.reference, &md);
        if (ref.image.width != o.common.width || ref.image.height != o.common.height)
            throw Error(o.reference + ": the reference is " + std::to_string(ref.image.width) + "x" +
                        std::to_string(ref.image.height) + "; expected " + std::to_string(o.common.width) + "x" +
                        std::to_string(o.common.height) + " (--width/--height)");
        if (auto it = md.find("pathview:expected_rel_mse"); it != md.end())
            ref.expected_rel_mse = std::stod(it->second);
        ref.origin = o.reference + (md.count("pathview:spp") ? " (" + md["pathview:spp"] + " spp)" : "");
        return ref;
    }
    // Two independent halves (seeds apart from the measured renders'), averaged. Their difference estimates the
    // reference's own error for any sampler: E[(A - B)^2] = 2 var(half) and var((A + B)/2) = var(half)/2, so the
    // average's relMSE is about relMSE(A, B) / 4.
    RenderSettings s = o.common.settings;
    s.sampler = o.reference_sampler;
    const uint32_t half_spp = std::max(1u, o.reference_spp / 2);
    Image halves[2];
    double seconds = 0.0;
    for (int h = 0; h < 2; ++h) {
        s.seed = 0x7265660u + o.common.settings.seed + uint32_t(h) * 0x9e3779b9u;
        renderer.restart(camera, s, o.common.width, o.common.height);
        while (renderer.stats().spp < half_spp) {
            renderer.render_pass();
            progress.draw(0.0, "reference " + std::to_string(h * half_spp + renderer.stats().spp) + "/" +
                                   std::to_string(2 * half_spp) + " spp");
        }
        halves[h] = renderer.film().mean();
        seconds += renderer.stats().seconds;
    }
    ref.image = halves[0];
    for (size_t i = 0; i < ref.image.rgb.size(); ++i) ref.image.rgb[i] = 0.5f * (halves[0].rgb[i] + halves[1].rgb[i]);
    ref.expected_rel_mse = compare_images(halves[0], halves[1]).rel_mse / 4.0;
    char buf[200];
    std::snprintf(buf, sizeof buf, "rendered: 2 x %u spp (%s sampler, %s), %.1f s", half_spp, sampler_name(s.sampler),
                  s.describe().c_str(), seconds);
    ref.origin = buf;
    if (!o.save_reference.empty()) {
        Metadata md = render_metadata(renderer);
        md["pathview:expected_rel_mse"] = std::to_string(ref.expected_rel_mse);
        md["pathview:spp"] = std::to_string(2 * half_spp);
        md["pathview:reference"] = ref.origin;
        write_exr(o.save_reference, ref.image, md);
    }
    return ref;
}

}  // namespace pv::app
