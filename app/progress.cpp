// app/progress.cpp: the CLI's progress bar (see progress.h).
#include "app/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace pv::app {

ProgressBar::ProgressBar(bool enabled) : m_enabled(enabled && isatty(STDERR_FILENO)) {}

void ProgressBar::draw(double fraction, const std::string& what) {
    if (!m_enabled) return;
    const auto now = std::chrono::steady_clock::now();
    if (fraction < 1.0 && std::chrono::duration<double>(now - m_last).count() < 0.1) return;
    m_last = now;
    const double f = std::clamp(fraction, 0.0, 1.0);
    const int width = 30, filled = static_cast<int>(f * width);
    std::fprintf(stderr, "\r[%s%s] %3d%%  %-48.48s", std::string(size_t(filled), '=').c_str(),
                 std::string(size_t(width - filled), ' ').c_str(), int(f * 100), what.c_str());
    std::fflush(stderr);
}

void ProgressBar::finish() {
    if (m_enabled) std::fprintf(stderr, "\n");
}

void ProgressBar::clear() {
    if (m_enabled) std::fprintf(stderr, "\r%90s\r", "");
}

}  // namespace pv::app
