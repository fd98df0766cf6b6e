#include "runtime/progress.hpp"

#include <algorithm>
#include <cstdlib>

namespace cf::runtime {

ProgressDisplay::ProgressDisplay(std::FILE* out, bool interactive) : out_(out), interactive_(interactive) {}

bool ProgressDisplay::loop_line_shown(int iteration) {
    if (iteration <= 0) return true;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_loop_line_ < std::chrono::seconds(1)) {
        ++skipped_lines_;
        return false;
    }
    last_loop_line_ = now;
    return true;
}

std::string ProgressDisplay::skipped_note() {
    if (skipped_lines_ == 0) return "";
    const std::string note = " (" + std::to_string(skipped_lines_) + " loop lines not shown)";
    skipped_lines_ = 0;
    return note;
}

std::string ProgressDisplay::label(const std::string& node, int iteration) const {
    return iteration >= 0 ? node + "#" + std::to_string(iteration) : node;
}

void ProgressDisplay::node_started(const std::string& node, int iteration) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string l = label(node, iteration);
    running_[l] = 0;
    label_of_[node] = l;
    last_quarter_[node] = 0;
    if (interactive_) redraw();
    else if (loop_line_shown(iteration)) {
        double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        std::fprintf(out_, "[%8.2f s] start  %s%s\n", t, l.c_str(), skipped_note().c_str());
        std::fflush(out_);
    }
}

void ProgressDisplay::node_finished(const std::string& node, int iteration, double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string l = label(node, iteration);
    running_.erase(l);
    if (!loop_line_shown(iteration)) {
        if (interactive_) redraw();
        return;
    }
    if (interactive_) {
        std::fprintf(out_, "\r\033[K  done  %-32s %8.3f s\n", l.c_str(), seconds);
        redraw();
    } else {
        double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        std::fprintf(out_, "[%8.2f s] done   %s (%.3f s)%s\n", t, l.c_str(), seconds, skipped_note().c_str());
    }
    std::fflush(out_);
}

void ProgressDisplay::progress(const std::string& node, double fraction) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = label_of_.find(node);
    if (it == label_of_.end()) return;
    fraction = std::clamp(fraction, 0.0, 1.0);
    running_[it->second] = fraction;
    if (interactive_) {
        auto now = std::chrono::steady_clock::now();
        if (now - last_draw_ > std::chrono::milliseconds(100)) redraw();
    } else {
        int quarter = static_cast<int>(fraction * 4);
        if (quarter > last_quarter_[node] && quarter < 4) {
            last_quarter_[node] = quarter;
            const auto hash = it->second.find('#');
            if (hash != std::string::npos && !loop_line_shown(std::atoi(it->second.c_str() + hash + 1))) return;
            std::fprintf(out_, "             %s %d%%\n", it->second.c_str(), quarter * 25);
            std::fflush(out_);
        }
    }
}

void ProgressDisplay::redraw() {
    last_draw_ = std::chrono::steady_clock::now();
    std::string line = "\r\033[K";
    for (const auto& [l, f] : running_) {
        const int width = 10, filled = static_cast<int>(f * width + 0.5);
        line += l + " [" + std::string(filled, '#') + std::string(width - filled, '-') + "] ";
    }
    std::fputs(line.c_str(), out_);
    std::fflush(out_);
}

void ProgressDisplay::finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (interactive_) std::fputs("\r\033[K", out_);
    std::fflush(out_);
}

}  // namespace cf::runtime
