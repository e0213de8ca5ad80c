// References that would read outside the scene's folder: each is refused with a
// SceneError naming the element that holds it, before anything is read.
#include <gtest/gtest.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

// A folder `scene/` for the scene and, beside it, a secret the scene must not reach.
struct Sandbox {
    TempDir dir;
    std::filesystem::path secret = dir.write("outside/secret.bin", Bytes(36, 0));
    std::filesystem::path scene_dir = dir.path() / "scene";
    Sandbox() { std::filesystem::create_directories(scene_dir); }

    std::string load_error(const std::string& file, const std::string& content) const {
        const std::filesystem::path path = dir.write("scene/" + file, content);
        return scene_error([&] { load_scene(path); });
    }
};

// A glTF whose only buffer (36 bytes: one triangle) is at `uri`.
std::string gltf_with_buffer(const std::string& uri) {
    GltfDoc doc;
    doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}});
    Json json = doc.json;
    json["buffers"] = {{{"byteLength", 36}, {"uri", uri}}};
    return json.dump();
}

std::string gltf_with_image(const std::string& uri) {
    Json json = Json::parse(gltf_with_buffer("data:application/octet-stream;base64," + base64(Bytes(36, 0))));
    json["images"] = {{{"uri", uri}}};
    return json.dump();
}

TEST(LoaderSecurity, ParentDirectoryEscapeIsRefused) {
    Sandbox box;
    const std::string error = box.load_error("a.gltf", gltf_with_buffer("../outside/secret.bin"));
    EXPECT_TRUE(contains(error, "a.gltf: buffers[0].uri '../outside/secret.bin' leads outside")) << error;
}

TEST(LoaderSecurity, PercentEncodedEscapeIsRefused) {
    Sandbox box;
    const std::string error = box.load_error("a.gltf", gltf_with_buffer("%2e%2e/outside/secret.bin"));
    EXPECT_TRUE(contains(error, "buffers[0].uri") && contains(error, "outside the scene folder")) << error;
}

TEST(LoaderSecurity, EscapeThroughASubfolderIsRefused) {
    Sandbox box;
    std::filesystem::create_directories(box.scene_dir / "sub");
    const std::string error = box.load_error("a.gltf", gltf_with_image("sub/../../outside/secret.bin"));
    EXPECT_TRUE(contains(error, "images[0].uri") && contains(error, "outside the scene folder")) << error;
}

TEST(LoaderSecurity, AbsolutePathIsRefused) {
    Sandbox box;
    const std::string error = box.load_error("a.gltf", gltf_with_buffer(box.secret.string()));
    EXPECT_TRUE(contains(error, "buffers[0].uri") && contains(error, "absolute path")) << error;
}

TEST(LoaderSecurity, UrlsAreRefused) {
    Sandbox box;
    for (const std::string uri : {"http://example.com/mesh.bin", "file:///etc/passwd", "https://x/y.png"}) {
        const std::string error = box.load_error("a.gltf", gltf_with_image(uri));
        EXPECT_TRUE(contains(error, "images[0].uri") && contains(error, "is a URL")) << error;
    }
}

TEST(LoaderSecurity, SymlinkedFileLeadingOutIsRefused) {
    Sandbox box;
    std::filesystem::create_symlink(box.secret, box.scene_dir / "mesh.bin");
    const std::string error = box.load_error("a.gltf", gltf_with_buffer("mesh.bin"));
    EXPECT_TRUE(contains(error, "buffers[0].uri 'mesh.bin'") && contains(error, "symbolic link")) << error;
}

TEST(LoaderSecurity, SymlinkedFolderLeadingOutIsRefused) {
    Sandbox box;
    std::filesystem::create_directory_symlink(box.secret.parent_path(), box.scene_dir / "assets");
    const std::string error = box.load_error("a.gltf", gltf_with_buffer("assets/secret.bin"));
    EXPECT_TRUE(contains(error, "buffers[0].uri 'assets/secret.bin'") && contains(error, "outside")) << error;
}

TEST(LoaderSecurity, SymlinkInsideTheFolderIsFine) {
    Sandbox box;
    box.dir.write("scene/real/mesh.bin", Bytes(36, 0));
    std::filesystem::create_directory_symlink(box.scene_dir / "real", box.scene_dir / "alias");
    const std::filesystem::path path = box.dir.write("scene/a.gltf", gltf_with_buffer("alias/mesh.bin"));
    EXPECT_NO_THROW(load_scene(path));
}

TEST(LoaderSecurity, MaterialLibraryOutsideTheFolderIsRefused) {
    Sandbox box;
    box.dir.write("outside/evil.mtl", "newmtl x\nKd 1 1 1\n");
    const std::string obj = "mtllib ../outside/evil.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::string error = box.load_error("a.obj", obj);
    EXPECT_TRUE(contains(error, "a.obj: mtllib '../outside/evil.mtl' leads outside")) << error;
    const std::string absolute = box.load_error("b.obj", "mtllib " + (box.secret.parent_path() / "evil.mtl").string() +
                                                               "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_TRUE(contains(absolute, "mtllib") && contains(absolute, "absolute path")) << absolute;
}

TEST(LoaderSecurity, TextureOutsideTheFolderIsRefused) {
    Sandbox box;
    box.dir.write("scene/m.mtl", "newmtl x\nmap_Kd ../outside/secret.bin\n");
    const std::string error = box.load_error("a.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
    EXPECT_TRUE(contains(error, "material 'x' map_Kd '../outside/secret.bin' leads outside")) << error;
}

TEST(LoaderSecurity, SidecarSymlinkLeadingOutIsRefused) {
    Sandbox box;
    box.dir.write("outside/extras.json", "{}");
    std::filesystem::create_symlink(box.dir.path() / "outside/extras.json", box.scene_dir / "a.rt.json");
    const std::string error = box.load_error("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_TRUE(contains(error, "sidecar 'a.rt.json' leads outside")) << error;
}

TEST(LoaderSecurity, ReferencesFromMemoryAreRefusedButDataUrisWork) {
    const std::string error = scene_error([] { load_text(gltf_with_buffer("mesh.bin"), "m.gltf"); });
    EXPECT_TRUE(contains(error, "m.gltf: buffers[0].uri 'mesh.bin'") && contains(error, "loaded from memory")) << error;
    const std::string obj = scene_error([] { load_text("mtllib m.mtl\nv 0 0 0\n", "m.obj"); });
    EXPECT_TRUE(contains(obj, "m.obj: mtllib 'm.mtl'") && contains(obj, "loaded from memory")) << obj;
    const std::string embedded = gltf_with_buffer("data:application/octet-stream;base64," + base64(Bytes(36, 0)));
    EXPECT_NO_THROW(load_text(embedded, "m.gltf"));
}

TEST(LoaderSecurity, UndecodableDataUriIsNotTakenForAFile) {
    const std::string error = scene_error([] { load_text(gltf_with_buffer("data:text/html,<b>hi</b>"), "m.gltf"); });
    EXPECT_TRUE(contains(error, "buffers[0].uri") && contains(error, "data: URI")) << error;
}

TEST(LoaderSecurity, DeviceFilesInsideTheFolderAreNotRead) {
    Sandbox box;
    std::filesystem::create_directories(box.scene_dir / "dir.bin");
    const std::string error = box.load_error("a.gltf", gltf_with_buffer("dir.bin"));
    EXPECT_TRUE(contains(error, "buffers[0].uri 'dir.bin' is not a regular file")) << error;
}

}  // namespace
}  // namespace rt
