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

// Reads and parses a JSON file. Throws Error(Io) if it cannot be read and Error(InvalidInput)
// "<file>: not valid JSON: <parser message with line and column>".
inline json readJsonFile(const std::filesystem::path& path) {
    const std::string text = readTextFile(path);
    try {
        return json::parse(text);
    } catch (const json::parse_error& e) {
        throw Error(ErrorKind::InvalidInput, path.string() + ": not valid JSON: " + e.what());
    }
}

}  // namespace strata::detail
