// Internal (not a public header): strict, typed reading of a JSON object for Strata's input files
// (materials, scenes). Every error is Error(InvalidInput) "<file>: <key path>: <what is wrong>".
#pragma once

#include "strata/core/error.h"
#include "strata/core/file.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace strata::detail {

using json = nlohmann::json;

// Reads typed values from a JSON object, naming "<file>: <path>.<key>" in every error, and
// rejecting keys it was never asked about.
class JsonObjectReader {
public:
    JsonObjectReader(const json& object, std::string where, std::string file)
        : mObject(object), mWhere(std::move(where)), mFile(std::move(file)) {
        if (!mObject.is_object())
            fail(mWhere, std::string("must be a JSON object, got ") + mObject.type_name());
    }

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw Error(ErrorKind::InvalidInput, mFile + ": " + key + ": " + what);
    }
    std::string keyPath(const std::string& key) const { return mWhere.empty() ? key : mWhere + "." + key; }
    bool has(const std::string& key) const { return mObject.contains(key); }

    std::optional<double> number(const std::string& key) {
        const json* value = find(key);
        if (!value) return std::nullopt;
        if (!value->is_number())
            fail(keyPath(key), std::string("must be a number, got ") + value->type_name());
        const double number = value->get<double>();
        if (!std::isfinite(number)) fail(keyPath(key), "must be a finite number");
        return number;
    }

    std::optional<long long> integer(const std::string& key, long long min, long long max) {
        const json* value = find(key);
        if (!value) return std::nullopt;
        if (!value->is_number_integer())
            fail(keyPath(key), std::string("must be an integer, got ") +
                                   (value->is_number() ? value->dump() : value->type_name()));
        const auto number = value->get<long long>();
        if (number < min || number > max)
            fail(keyPath(key), "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " +
                                   std::to_string(number));
        return number;
    }

    std::optional<std::string> string(const std::string& key) {
        const json* value = find(key);
        if (!value) return std::nullopt;
        if (!value->is_string())
            fail(keyPath(key), std::string("must be a string, got ") + value->type_name());
        return value->get<std::string>();
    }

    std::optional<bool> boolean(const std::string& key) {
        const json* value = find(key);
        if (!value) return std::nullopt;
        if (!value->is_boolean())
            fail(keyPath(key), std::string("must be true or false, got ") + value->type_name());
        return value->get<bool>();
    }

    const json* object(const std::string& key) {
        const json* value = find(key);
        if (value && !value->is_object())
            fail(keyPath(key), std::string("must be a JSON object, got ") + value->type_name());
        return value;
    }

    const json* array(const std::string& key) {
        const json* value = find(key);
        if (value && !value->is_array())
            fail(keyPath(key), std::string("must be an array, got ") + value->type_name());
        return value;
    }

    // Call after reading every known key: any other key is an error (a typo must not pass silently).
    void rejectUnknown(const std::set<std::string>& alsoAllowed = {}) const {
        for (const auto& [key, value] : mObject.items())
            if (!mSeen.count(key) && !alsoAllowed.count(key)) fail(keyPath(key), "unknown key");
    }

private:
    const json* find(const std::string& key) {
        mSeen.insert(key);
        const auto it = mObject.find(key);
        return it == mObject.end() ? nullptr : &*it;
    }

    const json& mObject;
    std::string mWhere;
    std::string mFile;
    std::set<std::string> mSeen;
};

// Parses JSON text strictly: a key twice in one object is an error (nlohmann keeps the last one, so a
// pasted block would silently win), and so is a number out of double's range (1e400). Throws
// Error(InvalidInput) "<where>: not valid JSON: <parser message with line and column>" or
// "<where>: <key path>: duplicate key".
inline json parseJsonStrict(const std::string& text, const std::string& where) {
    struct Open {  // an object or array being parsed
        bool array = false;
        std::size_t index = 0;       // of the next element, in an array
        std::string path;            // "layers[0]", for the message
        std::set<std::string> keys;  // seen so far, in an object
    };
    std::vector<Open> open;
    std::string lastKey;
    const auto childPath = [&]() {
        if (open.empty()) return std::string();
        const Open& parent = open.back();
        if (parent.array) return parent.path + "[" + std::to_string(parent.index) + "]";
        return parent.path.empty() ? lastKey : parent.path + "." + lastKey;
    };
    const auto elementDone = [&]() {
        if (!open.empty() && open.back().array) ++open.back().index;
    };
    const json::parser_callback_t callback = [&](int /*depth*/, json::parse_event_t event, json& parsed) {
        switch (event) {
            case json::parse_event_t::object_start:
                open.push_back({false, 0, childPath(), {}});
                break;
            case json::parse_event_t::array_start:
                open.push_back({true, 0, childPath(), {}});
                break;
            case json::parse_event_t::object_end:
            case json::parse_event_t::array_end:
                open.pop_back();
                elementDone();
                break;
            case json::parse_event_t::key:
                lastKey = parsed.get<std::string>();
                if (!open.back().keys.insert(lastKey).second)
                    throw Error(ErrorKind::InvalidInput, where + ": " + childPath() + ": duplicate key");
                break;
            case json::parse_event_t::value:
                elementDone();
                break;
        }
        return true;
    };
    try {
        return json::parse(text, callback);
    } catch (const json::exception& e) {
        throw Error(ErrorKind::InvalidInput, where + ": not valid JSON: " + e.what());
    }
}

// Reads and parses a JSON file with parseJsonStrict. Throws Error(Io) if it cannot be read.
inline json readJsonFile(const std::filesystem::path& path) {
    return parseJsonStrict(readTextFile(path), path.string());
}

}  // namespace strata::detail
