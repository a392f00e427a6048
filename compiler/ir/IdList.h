// A short list of ids (an instruction's operands, results or regions) kept inside the
// instruction for up to kInline entries, on the heap past that.
//
// Nearly every instruction has at most three operands, one result and no regions; with
// std::vector each of those lists cost a heap allocation, and the cleanup passes, which
// rebuild a function instruction by instruction several times, spent about half their time
// in malloc and free on a scene of 1,000 layers. The interface is the subset of std::vector
// the compiler uses, and a list converts to a std::vector where one is wanted.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <iterator>
#include <span>
#include <stdexcept>
#include <vector>

namespace moire::ir {

class IdList {
  public:
    using value_type = uint32_t;
    using size_type = size_t;
    using iterator = uint32_t*;
    using const_iterator = const uint32_t*;
    using reverse_iterator = std::reverse_iterator<iterator>;
    using const_reverse_iterator = std::reverse_iterator<const_iterator>;
    static constexpr uint32_t kInline = 3;

    IdList() = default;
    IdList(std::initializer_list<uint32_t> ids) { assignRange(ids.begin(), ids.size()); }
    IdList(const std::vector<uint32_t>& ids) { assignRange(ids.data(), ids.size()); }
    IdList(std::span<const uint32_t> ids) { assignRange(ids.data(), ids.size()); }
    IdList(const IdList& o) { assignRange(o.data(), o.size_); }
    IdList(IdList&& o) noexcept { steal(o); }
    ~IdList() { release(); }

    IdList& operator=(const IdList& o) {
        if (this != &o) {
            size_ = 0;
            assignRange(o.data(), o.size_);
        }
        return *this;
    }
    IdList& operator=(IdList&& o) noexcept {
        if (this != &o) {
            release();
            steal(o);
        }
        return *this;
    }
    IdList& operator=(std::initializer_list<uint32_t> ids) {
        size_ = 0;
        assignRange(ids.begin(), ids.size());
        return *this;
    }
    IdList& operator=(const std::vector<uint32_t>& ids) {
        size_ = 0;
        assignRange(ids.data(), ids.size());
        return *this;
    }

    operator std::vector<uint32_t>() const { return std::vector<uint32_t>(begin(), end()); }

    size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    uint32_t* data() { return cap_ > kInline ? heap_ : inline_; }
    const uint32_t* data() const { return cap_ > kInline ? heap_ : inline_; }
    uint32_t& operator[](size_t i) { return data()[i]; }
    const uint32_t& operator[](size_t i) const { return data()[i]; }
    uint32_t& at(size_t i) {
        if (i >= size_) throw std::out_of_range("IdList::at");
        return data()[i];
    }
    const uint32_t& at(size_t i) const {
        if (i >= size_) throw std::out_of_range("IdList::at");
        return data()[i];
    }
    uint32_t& front() { return data()[0]; }
    const uint32_t& front() const { return data()[0]; }
    uint32_t& back() { return data()[size_ - 1]; }
    const uint32_t& back() const { return data()[size_ - 1]; }

    iterator begin() { return data(); }
    iterator end() { return data() + size_; }
    const_iterator begin() const { return data(); }
    const_iterator end() const { return data() + size_; }
    reverse_iterator rbegin() { return reverse_iterator(end()); }
    reverse_iterator rend() { return reverse_iterator(begin()); }
    const_reverse_iterator rbegin() const { return const_reverse_iterator(end()); }
    const_reverse_iterator rend() const { return const_reverse_iterator(begin()); }

    void clear() { size_ = 0; }
    void pop_back() { --size_; }
    void push_back(uint32_t id) {
        if (size_ == cap_) grow(cap_ * 2);
        data()[size_++] = id;
    }
    void reserve(size_t n) {
        if (n > cap_) grow(static_cast<uint32_t>(n));
    }
    void assign(size_t n, uint32_t id) {
        size_ = 0;
        reserve(n);
        std::fill_n(data(), n, id);
        size_ = static_cast<uint32_t>(n);
    }

    friend bool operator==(const IdList& a, const IdList& b) {
        return std::equal(a.begin(), a.end(), b.begin(), b.end());
    }

  private:
    void assignRange(const uint32_t* ids, size_t n) {
        reserve(n);
        if (n) std::memcpy(data(), ids, n * sizeof(uint32_t));
        size_ = static_cast<uint32_t>(n);
    }
    void grow(uint32_t cap) {
        auto* bigger = new uint32_t[cap];
        if (size_) std::memcpy(bigger, data(), size_ * sizeof(uint32_t));
        release();
        heap_ = bigger;
        cap_ = cap;
    }
    void release() {
        if (cap_ > kInline) delete[] heap_;
        cap_ = kInline;
    }
    void steal(IdList& o) {
        size_ = o.size_;
        cap_ = o.cap_;
        if (o.cap_ > kInline)
            heap_ = o.heap_;
        else
            std::memcpy(inline_, o.inline_, sizeof inline_);
        o.size_ = 0;
        o.cap_ = kInline;
    }

    uint32_t size_ = 0;
    uint32_t cap_ = kInline;
    union {
        uint32_t inline_[kInline];
        uint32_t* heap_;
    };
};

} // namespace moire::ir
