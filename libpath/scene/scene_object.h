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

// The vocabulary a scene file is written in (mitsuba3_syntax.h): Mitsuba 0.4-0.6, or 2.x/3.x translated.
enum class SceneSyntax { Mitsuba06, Mitsuba3 };

struct Property {
    enum class Type { Float, Integer, Boolean, String, Spectrum, Point, Vector, Transform };
    Type type = Type::Float;
    double number = 0;        // float, integer
    bool boolean = false;
    std::string string;
    Spectrum spectrum;
    Vec3 vector;              // point, vector
    Transform transform;
    std::string name; // as written in the file (a Mitsuba 3 name before its translation)
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
    SceneSyntax syntax = SceneSyntax::Mitsuba06; // of that file (names below are already 0.6's)
    std::map<std::string, Property> props;
    std::vector<std::shared_ptr<const SceneObject>> children;   // nested objects and resolved refs
    // A <ref name="..."> that renames the object it refers to is a copy with the new name; `original` is
    // the object declared, so one declaration is built (and counted) once however it is referenced.
    const SceneObject* original = nullptr;
    [[nodiscard]] const SceneObject* declaration() const { return original ? original : this; }

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
};

// What is left unread once a plugin is built. Rendering hints (Mitsuba properties lt knows and has no use
// for, such as a film's gamma) are listed once per plugin and property. Any other unread property is one
// lt does not know: Mitsuba 0.5/0.6 warns about an unqueried property and renders, and so does lt, with one
// warning per plugin and property naming the first place and counting the others; strict loading
// (`--strict`) makes it an error naming file and line.
class UnreadProperties {
public:
    explicit UnreadProperties(bool strict) : strict_(strict) {}
    // Check o after its builder has read all it reads; `hints` are its known, ignored properties. A
    // declaration built more than once (a shape of an instanced shapegroup) is checked once.
    void check(const SceneObject& o, const std::set<std::string>& hints = {});
    // A hint that is not a property (e.g. a sampler type lt replaces by its own), listed once.
    void addHint(const std::string& hint);
    [[nodiscard]] const std::vector<std::string>& hints() const { return hints_; }
    [[nodiscard]] std::vector<std::string> warnings() const;

private:
    struct Unknown {
        std::string key;   // "<bsdf type=\"conductor\">: property 'alpha'"
        std::string first; // FILE:LINE of its first occurrence
        size_t others = 0;
    };
    bool strict_;
    std::set<const SceneObject*> checked_; // declarations
    std::vector<std::string> hints_;
    std::vector<Unknown> unknown_;
};

struct XmlDocument {
    std::shared_ptr<SceneObject> root;         // the <scene> element
    std::vector<std::string> filesRead;        // main file and includes, for the content hash
};

// Parse a Mitsuba scene file: version 0.4 to 0.6 as written, 2.x and 3.x translated into the 0.6
// vocabulary (mitsuba3_syntax.h), each file (and include) by its own version attribute; a file without one
// is read as 0.6. `parameters` override the scene's <default> values ($name substitution, as
// `mitsuba -D name=value`). Throws lt::Error("FILE:LINE: ...") on malformed XML, a version lt does not
// read, unknown elements, bad numbers, undefined ids or $names, include cycles.
XmlDocument parseSceneXml(const std::string& filename, const std::map<std::string, std::string>& parameters = {});

} // namespace lt
