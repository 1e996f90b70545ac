#include "sim/OdeMessages.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace mwb {
namespace {

struct Capture {
    std::vector<OdeMessage>* into = nullptr;
    double step_time_s = 0;
};
thread_local Capture t_capture;

std::string on_one_line(std::string text) {
    std::replace_if(text.begin(), text.end(), [](char c) { return c == '\t' || c == '\n' || c == '\r'; }, ' ');
    return text;
}

}  // namespace

OdeMessageCapture::OdeMessageCapture(std::vector<OdeMessage>& into, double step_time_s) {
    t_capture = {&into, step_time_s};
}

OdeMessageCapture::~OdeMessageCapture() { t_capture = {}; }

void record_ode_message(int code, const char* format, va_list args) {
    if (!t_capture.into) return;
    std::vector<OdeMessage>& messages = *t_capture.into;
    const auto same = std::find_if(messages.begin(), messages.end(), [&](const OdeMessage& m) { return m.code == code; });
    if (same != messages.end()) {
        ++same->times;
        return;
    }
    char text[256];
    std::vsnprintf(text, sizeof text, format, args);
    messages.push_back({code, on_one_line(text), t_capture.step_time_s, 1});
}

std::string encode_ode_messages(const std::vector<OdeMessage>& messages) {
    std::ostringstream out;
    out.precision(17);
    for (const OdeMessage& m : messages)
        out << m.code << '\t' << m.first_time_s << '\t' << m.times << '\t' << on_one_line(m.text) << '\n';
    return out.str();
}

std::vector<OdeMessage> decode_ode_messages(const std::string& text) {
    std::vector<OdeMessage> messages;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        std::istringstream fields(line);
        OdeMessage m;
        if (!(fields >> m.code >> m.first_time_s >> m.times) || fields.get() != '\t') continue;
        std::getline(fields, m.text);
        messages.push_back(std::move(m));
    }
    return messages;
}

}  // namespace mwb
