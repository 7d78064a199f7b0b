// A program's #include lines: resolved by the library against the program's own folder, so a
// program reads only files there. What a program includes is part of it: messages name the included
// file and line, and a changed included file rebuilds the program (its text is in the cache key).
// Every other form of include is refused with a message naming the including file and line.
#include "program/includes.hpp"
#include "support/error_expectations.hpp"
#include "support/test_support.hpp"

#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace clraster::test {
namespace {

namespace fs = std::filesystem;

// A folder of program files for one test, removed at its end.
class ProgramFolder : public ::testing::Test {
 protected:
  ProgramFolder() {
    fs::remove_all(folder_);
    fs::create_directories(folder_ / "lib");
  }
  ~ProgramFolder() override { fs::remove_all(folder_); }

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path path = folder_ / name;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    return path;
  }

  // resolve_includes on `source` as the file `name` of the folder.
  std::string resolved(const std::string& name, const std::string& source) const {
    return program::resolve_includes(source, (folder_ / name).string());
  }

  std::string shown(const std::string& name) const { return (folder_ / name).string(); }

  ProgramInterface resolved_interface(const std::string& name, const std::string& source) const {
    return Program::read_interface(source, shown(name));
  }

  const fs::path folder_ = fs::path(output_directory()) / "includes" /
                           ::testing::UnitTest::GetInstance()->current_test_info()->name();
};

// A program whose fragment colour is tint() from the included "lib/tint.cl".
const std::string kTinted = R"(clr_attribute(float2, corner)
clr_output(float4, color)
#include "lib/tint.cl"
void vertex(clr_vertex* v) { v->position = (float4)(v->in.corner, 0.0f, 1.0f); }
void fragment(clr_fragment* f) { f->out.color = tint(); }
)";

// The colour a program draws over a whole 4x4 framebuffer.
std::array<std::uint8_t, 4> drawn_colour(const Program& program) {
  Context& context = shared_context();
  const Buffer corners(context, std::vector<float>{-1, -1, 3, -1, -1, 3});
  Bindings bindings(program);
  DrawCall call;
  call.program = &program;
  call.bindings = &bindings;
  call.attributes = {{"corner", &corners, AttributeType::Float2}};
  Framebuffer framebuffer(context, 4, 4);
  framebuffer.clear({0, 0, 0, 0});
  framebuffer.draw(call);
  const Image image = framebuffer.read_color();
  return {image.rgba[0], image.rgba[1], image.rgba[2], image.rgba[3]};
}

TEST_F(ProgramFolder, IncludedFileIsPartOfTheProgramAndItsCacheKey) {
  write("lib/tint.cl", "float4 tint(void) { return (float4)(1.0f, 0.0f, 0.0f, 1.0f); }\n");
  const fs::path main = write("tinted.cl", kTinted);
  EXPECT_EQ(drawn_colour(Program::load(shared_context(), main.string())), (std::array<std::uint8_t, 4>{255, 0, 0, 255}));
  // The same program file, its include changed: a new program, not the cached one.
  write("lib/tint.cl", "float4 tint(void) { return (float4)(0.0f, 1.0f, 0.0f, 1.0f); }\n");
  EXPECT_EQ(drawn_colour(Program::load(shared_context(), main.string())), (std::array<std::uint8_t, 4>{0, 255, 0, 255}));
}

TEST_F(ProgramFolder, CompilerErrorsNameTheIncludedFileAndLine) {
  write("lib/tint.cl", "// a helper\nfloat4 tint(void) { return undefined_colour; }\n");
  const fs::path main = write("tinted.cl", kTinted);
  try {
    Program::load(shared_context(), main.string());
    ADD_FAILURE() << "the program compiled";
  } catch (const BuildError& error) {
    // Then the source line and a caret, as some compilers print them.
    EXPECT_TRUE(std::string_view(error.what())
                    .starts_with("program " + main.string() + " failed to compile:\n" + shown("lib/tint.cl") +
                                 ":2:28: error: use of undeclared identifier 'undefined_colour'"))
        << error.what();
  }
}

// Declarations may live in an included file; their messages name it.
TEST_F(ProgramFolder, DeclarationsInAnIncludedFileAreNamedWithItsLine) {
  write("lib/outputs.cl", "\n\nclr_output(float5, color)\n");
  EXPECT_TRUE(throws([&] { resolved_interface("main.cl", "#include \"lib/outputs.cl\"\n"); },
                     {shown("lib/outputs.cl") + ":3: output type 'float5' is not float4, int4 or uint4"}));
}

TEST_F(ProgramFolder, ProgramFileThatIsNotARegularFileIsNotRead) {
  const fs::path fifo = folder_ / "fifo.cl";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_TRUE(throws([&] { Program::load(shared_context(), fifo.string()); },
                     {"cannot read program file " + fifo.string() + ": not a regular file"}));
}

TEST_F(ProgramFolder, LinesAfterAnIncludeKeepTheirNumbers) {
  write("lib/empty.cl", "// nothing\n// at all\n");
  const std::string source = "clr_attribute(float2, corner)\n#include \"lib/empty.cl\"\nclr_uniform(float, a b)\n";
  EXPECT_TRUE(throws([&] { Program::read_interface(source, shown("main.cl")); },
                     {shown("main.cl") + ":3: uniform name 'a b' is not an identifier"}));
}

TEST_F(ProgramFolder, PathsAreRelativeToTheIncludingFile) {
  write("lib/inner.cl", "#define INNER 7\n");
  write("lib/outer.cl", "#include \"inner.cl\"\n");
  const std::string text = resolved("main.cl", "#include \"lib/outer.cl\"\nint x = INNER;\n");
  EXPECT_NE(text.find("#define INNER 7"), std::string::npos) << text;
  EXPECT_NE(text.find("#line 1 \"" + shown("lib/inner.cl") + "\""), std::string::npos) << text;
}

// Comments and strings are not code: an include in them is left alone (and not read).
TEST_F(ProgramFolder, IncludesInCommentsAreNotRead) {
  const std::string source = "// #include </etc/passwd>\n/* #include \"/etc/passwd\" */\nint x;\n";
  EXPECT_EQ(resolved("main.cl", source), source);
}

struct BadInclude {
  const char* name;
  std::string line;     // the #include line of main.cl, on its line 2
  std::string message;  // after "main.cl:2: "
};

class RefusedInclude : public ProgramFolder, public ::testing::WithParamInterface<BadInclude> {};

TEST_P(RefusedInclude, WithTheIncludingFileAndLine) {
  fs::create_directories(folder_.parent_path() / "outside");
  std::ofstream(folder_.parent_path() / "outside" / "secret.cl") << "#define SECRET 1\n";
  write("lib/self.cl", "#include \"self.cl\"\n");
  ::symlink((folder_.parent_path() / "outside" / "secret.cl").c_str(), (folder_ / "lib/link.cl").c_str());
  ::mkfifo((folder_ / "lib/fifo.cl").c_str(), 0600);
  std::string expected = GetParam().message;
  for (std::size_t at; (at = expected.find("FOLDER")) != std::string::npos;) expected.replace(at, 6, folder_.string());
  EXPECT_TRUE(throws([&] { resolved("main.cl", "int a;\n" + GetParam().line + "\nint b;\n"); }, {expected}));
}

INSTANTIATE_TEST_SUITE_P(
    Forms, RefusedInclude,
    ::testing::Values(
        BadInclude{"SystemHeader", "#include <stdio.h>",
                   "FOLDER/main.cl:2: #include <...> is not allowed: a program includes files of its own folder, as "
                   "#include \"file\""},
        BadInclude{"Macro", "#include PROGRAM_HEADER",
                   "FOLDER/main.cl:2: #include takes a file name in quotes, as #include \"file\", relative to the "
                   "program's folder"},
        BadInclude{"AbsolutePath", "#include \"/etc/passwd\"",
                   "FOLDER/main.cl:2: #include \"/etc/passwd\": an absolute path; a program includes files by paths "
                   "relative to its folder"},
        BadInclude{"ParentFolder", "#include \"../outside/secret.cl\"",
                   "FOLDER/main.cl:2: #include \"../outside/secret.cl\": the file is outside the program's folder "
                   "FOLDER"},
        BadInclude{"ParentFolderDeeper", "#include \"lib/../../outside/secret.cl\"",
                   "FOLDER/main.cl:2: #include \"lib/../../outside/secret.cl\": the file is outside the program's "
                   "folder FOLDER"},
        BadInclude{"LinkOutOfTheFolder", "#include \"lib/link.cl\"",
                   "FOLDER/main.cl:2: #include \"lib/link.cl\": the file is outside the program's folder FOLDER"},
        BadInclude{"Fifo", "#include \"lib/fifo.cl\"",
                   "FOLDER/main.cl:2: #include \"lib/fifo.cl\": cannot read FOLDER/lib/fifo.cl: not a regular file"},
        BadInclude{"Folder", "#include \"lib\"",
                   "FOLDER/main.cl:2: #include \"lib\": cannot read FOLDER/lib: not a regular file"},
        BadInclude{"Missing", "#include \"lib/missing.cl\"",
                   "FOLDER/main.cl:2: #include \"lib/missing.cl\": cannot read FOLDER/lib/missing.cl: No such file "
                   "or directory"},
        BadInclude{"Import", "#import \"lib/self.cl\"",
                   "FOLDER/main.cl:2: #import is not supported: use #include \"file\""},
        BadInclude{"SplitOverLines", "#inc\\\nlude \"lib/self.cl\"",
                   "FOLDER/main.cl:2: an #include directive split over lines"},
        BadInclude{"ItselfForEver", "#include \"lib/self.cl\"",
                   "FOLDER/lib/self.cl:1: #include \"self.cl\": includes nest more than 32 deep (does a file "
                   "include itself?)"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace clraster::test
