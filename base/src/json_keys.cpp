// Duplicate keys in JSON objects (surfgrad/base/io.h: checkJsonKeysUnique).
// RFC 8259 sec. 4 leaves repeated names to the implementation, and
// nlohmann_json (like most parsers) keeps one silently: a scene that sets
// "level" twice would render with whichever value the parser kept. One SAX
// pass over the text keeps the set of keys of every open object and the
// JSON Pointer of where it is.
#include <nlohmann/json.hpp>

#include <set>
#include <string>
#include <vector>

#include "surfgrad/base/io.h"

namespace sg::io {

namespace {

using json = nlohmann::json;

class KeyChecker : public nlohmann::json_sax<json> {
public:
    explicit KeyChecker(const std::string& file) : file_(file) {}

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override {
        open(true);
        return true;
    }
    bool key(string_t& k) override {
        Frame& f = stack_.back();
        if (!f.keys.insert(k).second)
            throw InputError(file_, pointer(stack_.size() - 1),
                             "duplicate key \"" + printable(k) + "\"");
        f.key = k;
        return true;
    }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override {
        open(false);
        return true;
    }
    bool end_array() override { return close(); }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
        return false; // malformed text: the caller's parser reports it
    }

private:
    struct Frame {
        bool object = false;
        std::set<std::string> keys; // objects: keys so far
        std::string key;            // objects: the key of the value being read
        std::size_t index = 0;      // arrays: the index of the value being read
    };
    // JSON Pointer of the container stack_[depth] (RFC 6901: "~" -> "~0",
    // "/" -> "~1").
    std::string pointer(std::size_t depth) const {
        std::string p;
        for (std::size_t d = 0; d < depth; ++d) {
            p += '/';
            if (!stack_[d].object) {
                p += std::to_string(stack_[d].index);
                continue;
            }
            for (char c : stack_[d].key) p += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
        }
        return p.empty() ? "/" : p;
    }
    void open(bool object) {
        Frame f;
        f.object = object;
        stack_.push_back(std::move(f));
    }
    bool close() {
        stack_.pop_back();
        return value();
    }
    // A value of the enclosing container is complete.
    bool value() {
        if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
        return true;
    }

    const std::string& file_;
    std::vector<Frame> stack_;
};

} // namespace

void checkJsonKeysUnique(std::string_view text, const std::string& file) {
    KeyChecker checker(file);
    json::sax_parse(text.begin(), text.end(), &checker);
}

} // namespace sg::io
