// ui/view_log.cpp: a flushed, timestamped line log.
#include "view_log.h"

#include <cerrno>
#include <chrono>
#include <cstdarg>
#include <cstring>

#include "core/base/error.h"

namespace pv::ui {
namespace {
double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

ViewLog::ViewLog(const std::string& path) : m_start(steady_seconds()) {
    if (path.empty()) return;
    m_file = std::fopen(path.c_str(), "w");
    if (!m_file) throw Error(path + ": cannot open the log file (" + std::strerror(errno) + ")");
}

ViewLog::~ViewLog() {
    if (m_file) std::fclose(m_file);
}

double ViewLog::now() const { return steady_seconds() - m_start; }

void ViewLog::line(const char* format, ...) {
    if (!m_file) return;
    std::fprintf(m_file, "%.3f ", now());
    va_list args;
    va_start(args, format);
    std::vfprintf(m_file, format, args);
    va_end(args);
    std::fputc('\n', m_file);
    std::fflush(m_file);
}

}  // namespace pv::ui
