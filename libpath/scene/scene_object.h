// The first stage of scene loading: the Mitsuba XML document as a tree of plugin descriptions
// (tag, type, id, properties, nested objects), with includes, defaults, $name substitution and refs
// already resolved. The second stage (scene_builder.cpp) turns it into a Scene. Keeping the stages apart
// lets every plugin be built from one uniform description and checked for unused properties.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "math/spectrum.h"
#include "math/transform.h"

namespace lt {

struct Property {
    enum class Type { Float, Integer, Boolean, String, Spectrum, Point, Vector, Transform };
    Type type = Type::Float;
    double number = 0;        // float, integer
    bool boolean = false;
    std::string string;
    Spectrum spectrum;
    Vec3 vector;              // point, vector
    Transform transform;
    int line = 0;
    mutable bool queried = false;
};

const char* propertyTypeName(Property::Type t);

struct SceneObject {
    std::string tag;          // shape, bsdf, texture, emitter, sensor, film, rfilter, sampler, integrator
    std::string type;         // plugin type, e.g. "obj"
    std::string id;           // id attribute (may be empty)
    std::string name;         // name attribute when nested as a named parameter (e.g. a texture "reflectance")
    std::string file;         // the XML file it came from
    int line = 0;
    std::map<std::string, Property> props;
    std::vector<std::shared_ptr<const SceneObject>> children;   // nested objects and resolved refs

    // "FILE:LINE: <tag type='type'>" for messages.
    [[nodiscard]] std::string where() const;
    // Throw lt::Error with where() prefixed.
    [[noreturn]] void fail(const std::string& message) const;

    // Typed getters: mark the property used; throw (naming file and line) on a wrong type.
    [[nodiscard]] bool has(const std::string& key) const { return props.count(key) != 0; }
    [[nodiscard]] double getFloat(const std::string& key, std::optional<double> def = {}) const;
    [[nodiscard]] int getInteger(const std::string& key, std::optional<int> def = {}) const;
    [[nodiscard]] bool getBoolean(const std::string& key, std::optional<bool> def = {}) const;
    [[nodiscard]] std::string getString(const std::string& key, std::optional<std::string> def = {}) const;
    // rgb, spectrum, or a float (a gray value), as Mitsuba accepts.
    [[nodiscard]] Spectrum getSpectrum(const std::string& key, std::optional<Spectrum> def = {}) const;
    [[nodiscard]] Vec3 getPoint(const std::string& key, std::optional<Vec3> def = {}) const;
    [[nodiscard]] Vec3 getVector(const std::string& key, std::optional<Vec3> def = {}) const;
    [[nodiscard]] Transform getTransform(const std::string& key, std::optional<Transform> def = {}) const;

    // Nested objects with a given tag (marks nothing: the builder consumes children explicitly).
    [[nodiscard]] std::vector<std::shared_ptr<const SceneObject>> childrenWithTag(const std::string& tag) const;
    [[nodiscard]] std::shared_ptr<const SceneObject> namedChild(const std::string& name) const;

    // Every property not read is an error naming it, except the given rendering hints, which are
    // returned so the caller can report them once as ignored.
    std::vector<std::string> checkUnused(const std::set<std::string>& ignorableHints) const;
};

struct XmlDocument {
    std::shared_ptr<SceneObject> root;         // the <scene> element
    std::vector<std::string> filesRead;        // main file and includes, for the content hash
};

// Parse a Mitsuba 0.5/0.6 scene file. `parameters` override the scene's <default> values ($name
// substitution, as `mitsuba -D name=value`). Throws lt::Error("FILE:LINE: ...") on malformed XML,
// unknown elements, bad numbers, undefined ids or $names, include cycles.
XmlDocument parseSceneXml(const std::string& filename, const std::map<std::string, std::string>& parameters = {});

} // namespace lt
