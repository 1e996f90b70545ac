#pragma once
// Little-endian serialization of fixed-width values. ByteReader checks every read against the
// end of its buffer: corrupted lengths become errors, never out-of-bounds reads.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mwb {

/// A malformed library file or record; the message says what and where.
struct LibraryError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Sampling into a library that holds another run (another scene, settings or base seed).
struct OtherRunError : LibraryError {
    using LibraryError::LibraryError;
};

class ByteWriter {
public:
    template <typename T>
    void put(T value) {
        static_assert(std::is_arithmetic_v<T>, "fixed-width numbers only");
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));  // the formats are little-endian, as is every target
        bytes_.insert(bytes_.end(), raw, raw + sizeof(T));
    }
    void put_bytes(const uint8_t* data, size_t size) { bytes_.insert(bytes_.end(), data, data + size); }
    /// u32 length, then the bytes.
    void put_blob(const std::vector<uint8_t>& blob) {
        put(static_cast<uint32_t>(blob.size()));
        put_bytes(blob.data(), blob.size());
    }
    void put_string(const std::string& text) {
        put(static_cast<uint32_t>(text.size()));
        put_bytes(reinterpret_cast<const uint8_t*>(text.data()), text.size());
    }
    std::vector<uint8_t>& bytes() { return bytes_; }

private:
    std::vector<uint8_t> bytes_;
};

class ByteReader {
public:
    /// `what` names the buffer in error messages (e.g. "world record at offset 1234").
    ByteReader(const uint8_t* data, size_t size, std::string what) : data_(data), size_(size), what_(std::move(what)) {}

    template <typename T>
    T get() {
        T value;
        std::memcpy(&value, take(sizeof(T)), sizeof(T));
        return value;
    }
    /// A u32-length-prefixed blob, as a pointer into the buffer.
    std::pair<const uint8_t*, size_t> get_blob() {
        const auto size = get<uint32_t>();
        return {take(size), size};
    }
    std::string get_string() {
        auto [data, size] = get_blob();
        return std::string(reinterpret_cast<const char*>(data), size);
    }
    /// Guards a count read from the data before allocating for it: each item needs at least
    /// `min_item_bytes`, so a count larger than what remains is corruption.
    size_t get_count(size_t min_item_bytes) {
        const auto count = get<uint32_t>();
        if (min_item_bytes > 0 && count > remaining() / min_item_bytes) fail("count " + std::to_string(count) + " exceeds the data");
        return count;
    }
    size_t remaining() const { return size_ - offset_; }
    size_t offset() const { return offset_; }
    [[noreturn]] void fail(const std::string& message) const {
        throw LibraryError(what_ + ", byte " + std::to_string(offset_) + ": " + message);
    }

private:
    const uint8_t* take(size_t n) {
        if (n > remaining()) fail("truncated (needs " + std::to_string(n) + " more bytes, " + std::to_string(remaining()) + " left)");
        const uint8_t* p = data_ + offset_;
        offset_ += n;
        return p;
    }

    const uint8_t* data_;
    size_t size_;
    size_t offset_ = 0;
    std::string what_;
};

}  // namespace mwb
