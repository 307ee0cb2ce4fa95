// The protobuf side of the kind declarations: every declared field is in its message with a
// matching type, every message field is declared, and the enums are the core's name lists.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <type_traits>

#include "convert/proto_fields.hpp"
#include "convert/scene_proto.hpp"
#include "tessera/scene/schema/kinds.hpp"

namespace tessera {
namespace {

namespace pb = google::protobuf;

template <typename Desc, typename Fields>
void expect_declared_fields_match(const pb::Descriptor* message, const Fields& fields,
                                  std::set<std::string> undeclared_ok = {}) {
  std::set<std::string> declared;
  for (const schema::Field<Desc>& field : fields) {
    if (!field.on_proto()) continue;
    declared.insert(std::string(field.name));
    if (message->FindOneofByName(std::string(field.name)) != nullptr) continue;  // a oneof
    const pb::FieldDescriptor* fd = message->FindFieldByName(std::string(field.name));
    ASSERT_NE(fd, nullptr) << message->full_name() << " has no field " << field.name;
    std::visit(
        [&](auto member) {
          using M = decltype(member);
          if constexpr (!std::is_same_v<M, std::monostate>) {
            using Value = std::remove_cvref_t<decltype(std::declval<Desc>().*member)>;
            pb::FieldDescriptor::Type expected = pb::FieldDescriptor::TYPE_MESSAGE;
            if constexpr (std::is_same_v<Value, double>)
              expected = pb::FieldDescriptor::TYPE_DOUBLE;
            if constexpr (std::is_same_v<Value, bool>) expected = pb::FieldDescriptor::TYPE_BOOL;
            if constexpr (std::is_same_v<Value, std::uint32_t>)
              expected = pb::FieldDescriptor::TYPE_UINT32;
            if constexpr (std::is_same_v<Value, std::string>)
              expected = pb::FieldDescriptor::TYPE_STRING;
            EXPECT_EQ(fd->type(), expected) << message->full_name() << "." << field.name;
            EXPECT_FALSE(fd->is_repeated()) << message->full_name() << "." << field.name;
            if constexpr (std::is_same_v<Value, glm::dvec3>) {
              EXPECT_EQ(fd->message_type()->name(), "Vec3") << field.name;
            }
            // A plain proto3 scalar reads 0 when unset: an optional one with a non-zero
            // default must say so (a required one is 0 when unset, like YAML's missing).
            if (field.presence == schema::Presence::kOptional && !fd->has_presence() &&
                fd->type() != pb::FieldDescriptor::TYPE_MESSAGE) {
              const Desc defaults{};
              if constexpr (std::is_arithmetic_v<Value>) {
                if (defaults.*member != Value{}) {
                  EXPECT_TRUE(field.zero_means_default)
                      << message->full_name() << "." << field.name
                      << ": non-zero default on a field without presence";
                }
              }
            }
          }
        },
        field.member);
  }
  for (int i = 0; i < message->field_count(); ++i) {
    const std::string name = message->field(i)->name();
    const pb::OneofDescriptor* oneof = message->field(i)->containing_oneof();
    if (oneof != nullptr && declared.count(oneof->name())) continue;  // a declared oneof's member
    EXPECT_TRUE(declared.count(name) || undeclared_ok.count(name))
        << message->full_name() << "." << name << " is not declared in schema/kinds.hpp";
  }
}

TEST(SchemaProto, EveryShapeKindIsAGeometryFieldWithItsDeclaredFields) {
  std::set<std::string> kinds;
  schema::for_each_kind<schema::ShapeKinds>([&](auto kind) {
    using Kind = decltype(kind);
    kinds.insert(std::string(Kind::proto_name));
    const pb::FieldDescriptor* fd =
        v1::Geometry::descriptor()->FindFieldByName(std::string(Kind::proto_name));
    ASSERT_NE(fd, nullptr) << Kind::proto_name;
    EXPECT_EQ(fd->containing_oneof()->name(), "shape");
    expect_declared_fields_match<typename Kind::Desc>(fd->message_type(), Kind::fields);
  });
  const pb::OneofDescriptor* shape = v1::Geometry::descriptor()->FindOneofByName("shape");
  EXPECT_EQ(static_cast<std::size_t>(shape->field_count()), kinds.size());
  for (int i = 0; i < shape->field_count(); ++i)
    EXPECT_TRUE(kinds.count(shape->field(i)->name())) << shape->field(i)->name() << " undeclared";
}

TEST(SchemaProto, TrimmedFaceSurfacesAreTheSurfaceKinds) {
  const pb::OneofDescriptor* surface = v1::TrimmedFace::descriptor()->FindOneofByName("surface");
  std::set<std::string> names;
  schema::for_each_kind<schema::SurfaceKinds>(
      [&](auto kind) { names.insert(std::string(schema::surface_proto_name<decltype(kind)>())); });
  ASSERT_EQ(static_cast<std::size_t>(surface->field_count()), names.size());
  for (int i = 0; i < surface->field_count(); ++i)
    EXPECT_TRUE(names.count(surface->field(i)->name())) << surface->field(i)->name();
}

TEST(SchemaProto, SectionsMaterialsAndTransformsMatchTheirMessages) {
  expect_declared_fields_match<CameraDesc>(v1::Camera::descriptor(), schema::CameraKind::fields);
  expect_declared_fields_match<BackgroundDesc>(v1::Background::descriptor(),
                                               schema::BackgroundKind::fields);
  expect_declared_fields_match<RenderSettings>(v1::RenderSettings::descriptor(),
                                               schema::RenderKind::fields);
  expect_declared_fields_match<MaterialDesc>(v1::Material::descriptor(),
                                             schema::MaterialKind::fields);
  expect_declared_fields_match<PatternDesc>(v1::Pattern::descriptor(), schema::PatternKind::fields);
  expect_declared_fields_match<TextureDesc>(v1::Texture::descriptor(), schema::TextureKind::fields);
  expect_declared_fields_match<LightDesc>(v1::Light::descriptor(), schema::LightKind::fields);
  expect_declared_fields_match<EnvironmentDesc>(v1::Environment::descriptor(),
                                                schema::EnvironmentKind::fields);
  expect_declared_fields_match<TransformDesc>(v1::Transform::descriptor(),
                                              schema::TransformKind::fields);
  expect_declared_fields_match<TransformDesc>(v1::Rotation::descriptor(),
                                              schema::RotationKind::fields);
}

// The proto enums are the core's lists: X_UNSPECIFIED, then X_<NAME> in the core's order.
void expect_enum_is(const pb::EnumDescriptor* e, std::string_view prefix,
                    std::span<const std::string_view> names) {
  ASSERT_EQ(static_cast<std::size_t>(e->value_count()), names.size() + 1) << e->full_name();
  EXPECT_EQ(e->value(0)->number(), 0);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const pb::EnumValueDescriptor* v =
        e->FindValueByName(proto_fields::enum_value_name(prefix, names[i]));
    ASSERT_NE(v, nullptr) << names[i];
    EXPECT_EQ(v->number(), static_cast<int>(i) + 1) << names[i];
  }
}

TEST(SchemaProto, EnumsAreTheCoreNameLists) {
  expect_enum_is(v1::MaterialType_descriptor(), "MATERIAL_TYPE_", material_type_names());
  expect_enum_is(v1::Integrator_descriptor(), "INTEGRATOR_", integrator_names());
  expect_enum_is(v1::Aov_descriptor(), "AOV_", aov_names());
  expect_enum_is(v1::Sampler_descriptor(), "SAMPLER_", sampler_names());
  expect_enum_is(v1::LightStrategy_descriptor(), "LIGHT_STRATEGY_", light_strategy_names());
}

// One rule, two path styles: the same mistake reads in the user's own terms on each side.
TEST(SchemaProto, ValidationSpeaksEachSidesPaths) {
  SceneDescription scene;
  scene.materials.emplace_back().name.assign(1, 'm');
  scene.disks.push_back(DiskDesc{
      .center = {}, .normal = {0, 1, 0}, .radius = 1.0, .inner_radius = 2.0, .source_index = 0});
  scene.render.samples_per_pixel = 0;
  scene.camera.fov_degrees = 200.0;
  const auto yaml = validate_scene(scene, {}, schema::PathStyle::kYaml);
  const auto proto = validate_scene(scene, {}, schema::PathStyle::kProto);
  ASSERT_EQ(yaml.size(), 3u);
  ASSERT_EQ(proto.size(), 3u);
  EXPECT_EQ(yaml[0].field, "camera.fov");
  EXPECT_EQ(proto[0].field, "camera.fov_degrees");
  EXPECT_EQ(yaml[1].field, "geometry[0].inner_radius");
  EXPECT_EQ(proto[1].field, "geometry[0].disk.inner_radius");
  EXPECT_EQ(yaml[2].field, "render.spp");
  EXPECT_EQ(proto[2].field, "settings.samples_per_pixel");
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(yaml[i].message, proto[i].message);
}

TEST(SchemaProto, RequiredVectorsAndDefaultsFollowTheDeclaration) {
  v1::Scene scene;
  v1::Material* m = scene.add_materials();
  m->set_name("m");
  m->set_type(v1::MATERIAL_TYPE_LAMBERTIAN);
  v1::Geometry* cylinder = scene.add_geometry();
  cylinder->set_material("m");
  cylinder->mutable_cylinder()->mutable_base();  // axis unset: the declared default +y
  cylinder->mutable_cylinder()->set_radius(1);
  cylinder->mutable_cylinder()->set_height(1);
  SceneConversion ok = scene_from_proto(scene, v1::RenderSettings());
  ASSERT_TRUE(ok.ok()) << describe_issues(ok.issues);
  EXPECT_EQ(ok.scene->cylinders[0].axis, glm::dvec3(0, 1, 0));
  EXPECT_EQ(ok.scene->render.samples_per_pixel, RenderSettings{}.samples_per_pixel);

  // proto3 has no required fields: an unset required vector is its zero value (the API's
  // documented rule), where YAML would say "is required but missing".
  v1::Geometry* sphere = scene.add_geometry();
  sphere->set_material("m");
  sphere->mutable_sphere()->set_radius(1);
  const SceneConversion converted = scene_from_proto(scene, v1::RenderSettings());
  ASSERT_TRUE(converted.ok()) << describe_issues(converted.issues);
  EXPECT_EQ(converted.scene->spheres[0].center, glm::dvec3(0.0));
  // A material's name is required and empty when unset: validate_scene names it.
  scene.mutable_materials(0)->clear_name();
  const SceneConversion unnamed = scene_from_proto(scene, v1::RenderSettings());
  ASSERT_FALSE(unnamed.issues.empty());
  EXPECT_EQ(unnamed.issues[0].to_string(), "materials[0].name: must not be empty");
}

}  // namespace
}  // namespace tessera
