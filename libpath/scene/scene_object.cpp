#include "scene/scene_object.h"

#include <algorithm>
#include <sstream>

#include "util/error.h"

namespace lt {

const char* propertyTypeName(Property::Type t) {
    switch (t) {
    case Property::Type::Float: return "float";
    case Property::Type::Integer: return "integer";
    case Property::Type::Boolean: return "boolean";
    case Property::Type::String: return "string";
    case Property::Type::Spectrum: return "rgb/spectrum";
    case Property::Type::Point: return "point";
    case Property::Type::Vector: return "vector";
    case Property::Type::Transform: return "transform";
    }
    return "?";
}

std::string SceneObject::where() const {
    std::ostringstream s;
    s << file << ':' << line << ": <" << tag;
    if (!type.empty()) s << " type=\"" << type << '"';
    if (!id.empty()) s << " id=\"" << id << '"';
    s << '>';
    return s.str();
}

void SceneObject::fail(const std::string& message) const { throw Error(where() + ": " + message); }

namespace {

const Property* lookup(const SceneObject& o, const std::string& key, std::initializer_list<Property::Type> types) {
    auto it = o.props.find(key);
    if (it == o.props.end()) return nullptr;
    const Property& p = it->second;
    for (auto t : types)
        if (p.type == t) {
            p.queried = true;
            return &p;
        }
    std::string expected;
    for (auto t : types) expected += (expected.empty() ? "" : " or ") + std::string(propertyTypeName(t));
    throw Error(o.file + ':' + std::to_string(p.line) + ": property '" + p.name + "' of <" + o.tag + " type=\"" +
                o.type + "\"> must be " + expected + ", not " + propertyTypeName(p.type));
}

template <class T> T missing(const SceneObject& o, const std::string& key, const std::optional<T>& def) {
    if (def) return *def;
    o.fail("missing required property '" + key + "'");
}

} // namespace

double SceneObject::getFloat(const std::string& key, std::optional<double> def) const {
    if (auto p = lookup(*this, key, {Property::Type::Float, Property::Type::Integer})) return p->number;
    return missing(*this, key, def);
}

int SceneObject::getInteger(const std::string& key, std::optional<int> def) const {
    if (auto p = lookup(*this, key, {Property::Type::Integer})) return int(p->number);
    return missing(*this, key, def);
}

bool SceneObject::getBoolean(const std::string& key, std::optional<bool> def) const {
    if (auto p = lookup(*this, key, {Property::Type::Boolean})) return p->boolean;
    return missing(*this, key, def);
}

std::string SceneObject::getString(const std::string& key, std::optional<std::string> def) const {
    if (auto p = lookup(*this, key, {Property::Type::String})) return p->string;
    return missing(*this, key, def);
}

Spectrum SceneObject::getSpectrum(const std::string& key, std::optional<Spectrum> def) const {
    if (auto p = lookup(*this, key, {Property::Type::Spectrum, Property::Type::Float, Property::Type::Integer}))
        return p->type == Property::Type::Spectrum ? p->spectrum : Spectrum(p->number);
    return missing(*this, key, def);
}

Vec3 SceneObject::getPoint(const std::string& key, std::optional<Vec3> def) const {
    if (auto p = lookup(*this, key, {Property::Type::Point})) return p->vector;
    return missing(*this, key, def);
}

Vec3 SceneObject::getVector(const std::string& key, std::optional<Vec3> def) const {
    if (auto p = lookup(*this, key, {Property::Type::Vector, Property::Type::Point})) return p->vector;
    return missing(*this, key, def);
}

Transform SceneObject::getTransform(const std::string& key, std::optional<Transform> def) const {
    if (auto p = lookup(*this, key, {Property::Type::Transform})) return p->transform;
    return missing(*this, key, def);
}

std::vector<std::shared_ptr<const SceneObject>> SceneObject::childrenWithTag(const std::string& t) const {
    std::vector<std::shared_ptr<const SceneObject>> out;
    for (const auto& c : children)
        if (c->tag == t) out.push_back(c);
    return out;
}

std::shared_ptr<const SceneObject> SceneObject::namedChild(const std::string& n) const {
    for (const auto& c : children)
        if (c->name == n) return c;
    return nullptr;
}

void UnreadProperties::check(const SceneObject& o, const std::set<std::string>& hints) {
    if (!checked_.insert(o.declaration()).second) return;
    for (const auto& [key, p] : o.props) {
        if (p.queried) continue;
        const std::string plugin = "<" + o.tag + " type=\"" + o.type + "\">";
        const std::string place = o.file + ':' + std::to_string(p.line);
        if (hints.count(key)) {
            addHint(o.tag + " " + o.type + ": " + p.name);
            continue;
        }
        if (strict_)
            throw Error(place + ": " + plugin + " does not read the property '" + p.name +
                        "' (an error with --strict; without it lt warns and ignores it, as Mitsuba 0.6 does)");
        const std::string k = plugin + ": property '" + p.name + "'";
        auto it = std::find_if(unknown_.begin(), unknown_.end(), [&](const Unknown& u) { return u.key == k; });
        if (it == unknown_.end())
            unknown_.push_back({k, place});
        else
            ++it->others;
    }
}

void UnreadProperties::addHint(const std::string& hint) {
    if (std::find(hints_.begin(), hints_.end(), hint) == hints_.end()) hints_.push_back(hint);
}

std::vector<std::string> UnreadProperties::warnings() const {
    std::vector<std::string> out;
    for (const auto& u : unknown_)
        out.push_back(u.first + ": " + u.key + " is not read by lt and was ignored" +
                      (u.others ? " (also at " + std::to_string(u.others) + " other place(s))" : "") +
                      "; --strict makes this an error");
    return out;
}

} // namespace lt
