#pragma once
// What ODE says through its message handler while a world steps (in ODE 0.16, quickstep's "LCP
// internal error"), kept with the world instead of being printed or dropped, so that the engine
// can warn of it. Messages carry no body; they are reported by world and time.
#include <cstdarg>
#include <cstdint>
#include <string>
#include <vector>

namespace mwb {

/// One kind of message (ODE's message number) a world gave.
struct OdeMessage {
    int code = 0;             ///< ODE's message number (d_ERR_LCP, ...)
    std::string text;         ///< the first message of this number in the world
    double first_time_s = 0;  ///< when the step that first gave it began
    uint32_t times = 0;       ///< how many messages of this number the world gave
};

/// While alive, ODE's messages on this thread go to `into` (one entry per message number), as
/// given by the step that begins at `step_time_s`. Scopes do not nest.
class OdeMessageCapture {
public:
    OdeMessageCapture(std::vector<OdeMessage>& into, double step_time_s);
    ~OdeMessageCapture();
    OdeMessageCapture(const OdeMessageCapture&) = delete;
    OdeMessageCapture& operator=(const OdeMessageCapture&) = delete;
};

/// ODE's message handler (dSetMessageHandler): to the capture of this thread, if any.
void record_ode_message(int code, const char* format, va_list args);

/// `messages` as one line per kind, for a worker's record; tabs and line breaks in texts become
/// spaces. decode_ode_messages reads it back (malformed lines are skipped).
std::string encode_ode_messages(const std::vector<OdeMessage>& messages);
std::vector<OdeMessage> decode_ode_messages(const std::string& text);

}  // namespace mwb
