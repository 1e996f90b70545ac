// Motion codec benchmarks on sampled worlds: size per body-frame, size against zlib on the same
// motion quantized to the same bounds, decode throughput, and a rate-distortion table.
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <vector>

#include "BenchReport.h"
#include "codec/PositionDecoder.h"
#include "codec/PositionEncoder.h"
#include "codec/RotationDecoder.h"
#include "codec/RotationEncoder.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"

namespace mwb::bench {
namespace {

struct Track {
    std::vector<double> positions;     // (frames, 3)
    std::vector<double> orientations;  // (frames, 4)
};

struct Corpus {
    std::string name;
    Vec3 gravity;
    std::vector<Track> tracks;  // active bodies of every sampled world
    uint64_t body_frames = 0;
};

Corpus sample_corpus(const std::string& file, uint64_t worlds) {
    CompiledScene compiled(load_scene_file(data_path(file)), SimulationParameters{});
    Corpus corpus{file, compiled.scene().world.gravity, {}, 0};
    sample_worlds(compiled, 1, 0, worlds, 0, [&](WorldResult&& w) {
        const size_t frames = w.frame_count;
        for (uint32_t b = 0; b < w.body_count; ++b) {
            if (!compiled.bodies()[b].dynamic) continue;
            Track t;
            t.positions.assign(w.positions_m.begin() + b * frames * 3, w.positions_m.begin() + (b + 1) * frames * 3);
            t.orientations.assign(w.orientations.begin() + b * frames * 4, w.orientations.begin() + (b + 1) * frames * 4);
            corpus.body_frames += frames;
            corpus.tracks.push_back(std::move(t));
        }
    });
    return corpus;
}

uint32_t frames_of(const Track& t) { return static_cast<uint32_t>(t.positions.size() / 3); }

size_t our_bytes(const Corpus& c, const CodecBounds& bounds, bool rotations = true) {
    size_t bytes = 0;
    for (const Track& t : c.tracks) {
        bytes += encode_position_track(t.positions.data(), frames_of(t), 1.0 / 120, c.gravity, bounds.position_error_max_m).size();
        if (rotations) bytes += encode_rotation_track(t.orientations.data(), frames_of(t), bounds.rotation_error_max_rad).size();
    }
    return bytes;
}

// The same motion quantized to the same bounds as integers (positions int32 per axis with a step
// whose worst Euclidean error is e_max; quaternion components int16 with a step whose worst angle
// error is below theta_max), frame-to-frame differenced, then deflated at level 9.
size_t zlib_bytes(const Corpus& c, const CodecBounds& bounds) {
    const double position_step = 2 * bounds.position_error_max_m / std::sqrt(3.0);
    const double rotation_step = bounds.rotation_error_max_rad / 4;
    std::vector<uint8_t> raw;
    auto put = [&raw](const void* p, size_t n) { raw.insert(raw.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n); };
    for (const Track& t : c.tracks) {
        int32_t previous_p[3] = {0, 0, 0};
        int16_t previous_q[4] = {0, 0, 0, 0};
        for (uint32_t f = 0; f < frames_of(t); ++f) {
            for (int k = 0; k < 3; ++k) {
                const auto q = static_cast<int32_t>(std::lround(t.positions[3 * f + k] / position_step));
                const int32_t d = q - previous_p[k];
                put(&d, 4);
                previous_p[k] = q;
            }
            for (int k = 0; k < 4; ++k) {
                const auto q = static_cast<int16_t>(std::lround(t.orientations[4 * f + k] / rotation_step));
                const auto d = static_cast<int16_t>(q - previous_q[k]);
                put(&d, 2);
                previous_q[k] = q;
            }
        }
    }
    uLongf size = compressBound(raw.size());
    std::vector<uint8_t> packed(size);
    compress2(packed.data(), &size, raw.data(), raw.size(), 9);
    return size;
}

double encode_body_frames_per_s(const Corpus& c) {
    uint64_t frames = 0;
    const auto start = std::chrono::steady_clock::now();
    do {
        for (const Track& t : c.tracks) {
            encode_position_track(t.positions.data(), frames_of(t), 1.0 / 120, c.gravity, 0.001);
            encode_rotation_track(t.orientations.data(), frames_of(t), 0.5 * M_PI / 180);
            frames += frames_of(t);
        }
    } while (seconds_since(start) < 0.5);
    return static_cast<double>(frames) / seconds_since(start);
}

double decode_body_frames_per_s(const Corpus& c) {
    std::vector<std::vector<uint8_t>> positions, rotations;
    for (const Track& t : c.tracks) {
        positions.push_back(encode_position_track(t.positions.data(), frames_of(t), 1.0 / 120, c.gravity, 0.001));
        rotations.push_back(encode_rotation_track(t.orientations.data(), frames_of(t), 0.5 * M_PI / 180));
    }
    std::vector<double> out(4 * 100000);
    uint64_t frames = 0;
    const auto start = std::chrono::steady_clock::now();
    do {
        for (size_t k = 0; k < positions.size(); ++k) {
            PositionTrackDecoder(positions[k]).decode_all(out.data());
            RotationTrackDecoder(rotations[k]).decode_all(out.data());
            frames += frames_of(c.tracks[k]);
        }
    } while (seconds_since(start) < 0.5);
    return static_cast<double>(frames) / seconds_since(start);
}

}  // namespace
}  // namespace mwb::bench

int main() {
    using namespace mwb;
    using namespace mwb::bench;
    std::printf("Motion codec on sampled worlds (active bodies only; raw float32 pose = 28 bytes)\n");
    const std::vector<Corpus> corpora{sample_corpus("pile50.json", 8), sample_corpus("chain.json", 8)};
    const CodecBounds defaults;
    const char* short_names[] = {"pile50", "chain"};
    for (size_t k = 0; k < corpora.size(); ++k) {
        const Corpus& c = corpora[k];
        const double ours = static_cast<double>(our_bytes(c, defaults));
        report(std::string("codec_bytes_per_body_frame_") + short_names[k], ours / static_cast<double>(c.body_frames),
               "bytes", "1 mm, 0.5 deg");
        report(std::string("codec_vs_zlib_ratio_") + short_names[k], ours / static_cast<double>(zlib_bytes(c, defaults)),
               "x", "ours / zlib-9 of delta-coded quantized ints (target <= 0.5)");
    }
    report("codec_bytes_per_body_frame", static_cast<double>(our_bytes(corpora[0], defaults)) / corpora[0].body_frames,
           "bytes", "headline: 50-body pile");
    report("codec_vs_zlib_ratio", static_cast<double>(our_bytes(corpora[0], defaults)) / zlib_bytes(corpora[0], defaults),
           "x", "headline: 50-body pile");
    report("decode_body_frames_per_s", decode_body_frames_per_s(corpora[0]), "frames/s", "position + rotation, 1 thread");
    report("encode_body_frames_per_s", encode_body_frames_per_s(corpora[0]), "frames/s", "position + rotation, 1 thread");
    report("encode_body_frames_per_s_chain", encode_body_frames_per_s(corpora[1]), "frames/s", "position + rotation, 1 thread");

    std::ofstream csv("rate_distortion.csv");
    csv << "scene,position_error_max_m,position_bytes_per_body_frame\n";
    std::printf("\n  rate-distortion (position tracks only)\n  %-10s %12s %14s\n", "scene", "e_max (m)", "bytes/frame");
    for (size_t k = 0; k < corpora.size(); ++k) {
        for (double bound : {1e-4, 3e-4, 1e-3, 3e-3, 1e-2}) {
            CodecBounds b;
            b.position_error_max_m = bound;
            const double per = static_cast<double>(our_bytes(corpora[k], b, false)) / corpora[k].body_frames;
            std::printf("  %-10s %12.4g %14.4f\n", short_names[k], bound, per);
            csv << short_names[k] << "," << bound << "," << per << "\n";
        }
    }
    std::printf("  (saved as rate_distortion.csv)\n");
    return 0;
}
