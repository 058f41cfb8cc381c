// Quake 3 shader scripts: every stage, culling, nodraw/sky/fog, the passes
// ioquake3 draws (multitexture collapse, blending, sort keys), and
// tolerance of malformed scripts.
#include <gtest/gtest.h>

#include <memory>

#include "oovr/scene/formats/q3_shader.h"

namespace oovr {
namespace {

const char* kScript = R"(// comment
textures/base/lit
{
	qer_editorimage textures/base/lit_editor.tga
	{
		map $lightmap
	}
	{
		map textures/base/Lit.tga   // the diffuse stage
		blendFunc GL_DST_COLOR GL_ZERO
		tcMod scale 2 4
	}
}
textures/base/fence
{
	cull none
	surfaceparm trans
	{
		clampmap textures/base/fence.tga
		alphaFunc GE128
		depthWrite
	}
}
textures/common/caulk
{
	surfaceparm nodraw
}
textures/skies/night
{
	surfaceparm sky
	skyparms env/night - -
}
textures/fog/green { fogparms ( 0 1 0 ) 512 }
/* block
   comment */
textures/anim/fire
{
	{ animMap 5 textures/anim/fire1.tga textures/anim/fire2.tga
	  blendfunc add }
}
textures/only/editor
{
	qer_editorimage textures/only/editor.jpg
}
)";

TEST(Q3Shader, ParsesEveryStage) {
  Q3ShaderSet set;
  parse_q3_shader_script(kScript, "scripts/test.shader", set);
  EXPECT_TRUE(set.notes.empty()) << set.notes.front();
  ASSERT_EQ(set.shaders.size(), 7u);
  const Q3Shader& lit = set.shaders.at("textures/base/lit");
  ASSERT_EQ(lit.stages.size(), 2u);
  EXPECT_EQ(lit.stages[0].source, Q3Stage::Source::lightmap);
  EXPECT_TRUE(lit.stages[0].tc_lightmap);
  EXPECT_EQ(lit.stages[1].image, "textures/base/Lit.tga");
  EXPECT_EQ(lit.stages[1].src, BlendFactor::dst_colour);
  EXPECT_EQ(lit.stages[1].dst, BlendFactor::zero);
  EXPECT_FALSE(lit.stages[1].depth_write) << "blended stages write no depth unless they say depthWrite";
  ASSERT_EQ(lit.stages[1].mods.size(), 1u);
  EXPECT_FLOAT_EQ(lit.stages[1].mods[0].s, 2);
  EXPECT_FLOAT_EQ(lit.stages[1].mods[0].t, 4);
  const Q3Shader& fence = set.shaders.at("textures/base/fence");
  EXPECT_TRUE(fence.two_sided);
  ASSERT_EQ(fence.stages.size(), 1u);
  EXPECT_TRUE(fence.stages[0].clamp);
  EXPECT_EQ(fence.stages[0].alpha_func, AlphaFunc::gequal);
  EXPECT_FLOAT_EQ(fence.stages[0].alpha_ref, 0.5f);
  EXPECT_TRUE(fence.stages[0].depth_write);
  EXPECT_TRUE(set.shaders.at("textures/common/caulk").nodraw);
  EXPECT_TRUE(set.shaders.at("textures/skies/night").sky);
  EXPECT_EQ(set.shaders.at("textures/skies/night").sky_box, "env/night");
  EXPECT_TRUE(set.shaders.at("textures/fog/green").fog);
  const Q3Stage& fire = set.shaders.at("textures/anim/fire").stages.at(0);
  EXPECT_EQ(fire.image, "textures/anim/fire1.tga");
  EXPECT_EQ(fire.src, BlendFactor::one);
  EXPECT_EQ(fire.dst, BlendFactor::one);
  EXPECT_EQ(set.shaders.at("textures/only/editor").editor_image, "textures/only/editor.jpg");
}

// Images get indices from 10 up in the order asked; the lightmap is 5.
struct FakeTextures : Q3TextureLookup {
  int lm = 5;
  std::vector<std::string> asked;
  int image(const Q3Stage& st) override {
    asked.push_back(st.image);
    return 10 + int(asked.size()) - 1;
  }
  int lightmap() override { return lm; }
};

Q3Shader parse_one(const std::string& body) {
  Q3ShaderSet set;
  parse_q3_shader_script("s " + body, "t.shader", set);
  EXPECT_TRUE(set.notes.empty()) << set.notes.front();
  return set.shaders.at("s");
}

TEST(Q3Shader, LightmapTimesImageCollapsesIntoOneMultitexturePass) {
  FakeTextures tex;
  const Q3Shader sh = parse_one("{ { map $lightmap } { map a.tga\n blendFunc filter } }");
  const Q3Passes q = q3_passes(&sh, tex);
  ASSERT_EQ(q.passes.size(), 1u);
  EXPECT_EQ(q.collapsed, 1);
  EXPECT_EQ(q.sort, q3_sort::opaque);
  const Pass& p = q.passes[0];
  ASSERT_EQ(p.layers.size(), 2u);
  EXPECT_EQ(p.layers[0].kind, LayerKind::diffuse) << "the image in unit 0, the lightmap in unit 1";
  EXPECT_EQ(p.layers[0].texture, 10);
  EXPECT_EQ(p.layers[1].kind, LayerKind::lightmap);
  EXPECT_EQ(p.layers[1].texture, 5);
  EXPECT_EQ(p.layers[1].coords, TexCoords::lightmap);
  EXPECT_EQ(p.layers[1].combine, Combine::modulate);
  EXPECT_FALSE(p.blended());
  EXPECT_TRUE(p.depth_write);
  EXPECT_EQ(p.depth_func, DepthFunc::lequal);
  // No script: ioquake3's implicit shader is the same pass.
  FakeTextures t2;
  const Q3Passes implicit = q3_passes(nullptr, t2);
  ASSERT_EQ(implicit.passes.size(), 1u);
  EXPECT_EQ(implicit.passes[0].layers.size(), 2u);
  // Without a lightmap (vertex lit): the image alone.
  FakeTextures t3;
  t3.lm = -1;
  const Q3Passes vertex = q3_passes(nullptr, t3);
  ASSERT_EQ(vertex.passes.size(), 1u);
  EXPECT_EQ(vertex.passes[0].layers.size(), 1u);
}

TEST(Q3Shader, StagesAfterTheCollapseAreBlendedPasses) {
  FakeTextures tex;
  const Q3Shader sh = parse_one(
      "{ { map $lightmap } { map a.tga\n blendFunc GL_DST_COLOR GL_ZERO } { map d.tga\n blendFunc GL_DST_COLOR GL_SRC_COLOR\n "
      "detail\n tcMod scale 9 9 } { map g.tga\n blendFunc add\n tcMod scroll 0.5 0 } }");
  const Q3Passes q = q3_passes(&sh, tex);
  ASSERT_EQ(q.passes.size(), 3u);
  EXPECT_EQ(q.passes[1].layers.at(0).kind, LayerKind::detail);
  EXPECT_EQ(q.passes[1].src, BlendFactor::dst_colour);
  EXPECT_EQ(q.passes[1].dst, BlendFactor::src_colour);
  EXPECT_TRUE(q.passes[1].reads_colour());
  EXPECT_FALSE(q.passes[1].depth_write);
  EXPECT_EQ(q.passes[2].src, BlendFactor::one);
  EXPECT_EQ(q.passes[2].dst, BlendFactor::one);
  EXPECT_EQ(q.passes[2].layers.at(0).mods.at(0).kind, TexMod::Kind::scroll);
  EXPECT_EQ(q.sort, q3_sort::opaque) << "the first stage is opaque";
}

TEST(Q3Shader, CollapseFollowsTheEnginesTable) {
  FakeTextures tex;
  // Opaque then add: GL_ADD multitexture, opaque.
  Q3Passes q = q3_passes(std::make_unique<Q3Shader>(parse_one("{ { map a.tga } { map b.tga\n blendFunc add } }")).get(), tex);
  ASSERT_EQ(q.passes.size(), 1u);
  EXPECT_EQ(q.passes[0].layers.at(1).combine, Combine::add);
  EXPECT_FALSE(q.passes[0].blended());
  // Add then add: one additive pass.
  q = q3_passes(std::make_unique<Q3Shader>(parse_one("{ { map a.tga\n blendFunc add } { map b.tga\n blendFunc add } }")).get(),
                tex);
  ASSERT_EQ(q.passes.size(), 1u);
  EXPECT_EQ(q.passes[0].src, BlendFactor::one);
  EXPECT_EQ(q.passes[0].dst, BlendFactor::one);
  EXPECT_EQ(q.sort, q3_sort::blend0);
  // Different alpha functions, or an alpha blend second: two passes.
  q = q3_passes(
      std::make_unique<Q3Shader>(parse_one("{ { map a.tga\n alphaFunc GE128 } { map $lightmap\n blendFunc filter } }")).get(),
      tex);
  EXPECT_EQ(q.passes.size(), 2u);
  q = q3_passes(std::make_unique<Q3Shader>(parse_one("{ { map a.tga } { map b.tga\n blendFunc blend } }")).get(), tex);
  EXPECT_EQ(q.passes.size(), 2u);
  EXPECT_EQ(q.passes[1].src, BlendFactor::src_alpha);
}

TEST(Q3Shader, SortKeysAsFinishShaderDecidesThem) {
  FakeTextures tex;
  const auto sort_of = [&](const std::string& body) {
    const Q3Shader sh = parse_one(body);
    return q3_passes(&sh, tex).sort;
  };
  EXPECT_EQ(sort_of("{ { map a.tga\n blendFunc blend } }"), q3_sort::blend0);
  EXPECT_EQ(sort_of("{ { map a.tga\n blendFunc blend\n depthWrite } }"), q3_sort::see_through);
  EXPECT_EQ(sort_of("{ sort nearest\n { map a.tga } }"), q3_sort::nearest);
  EXPECT_EQ(sort_of("{ sort 7\n { map a.tga } }"), 7.0f);
  EXPECT_EQ(sort_of("{ polygonOffset\n { map a.tga } }"), q3_sort::decal);
  EXPECT_EQ(sort_of("{ surfaceparm sky\n { map a.tga } }"), q3_sort::environment);
  EXPECT_EQ(sort_of("{ { map a.tga } }"), q3_sort::opaque);
}

TEST(Q3Shader, ConstantColoursAndUnsupportedModifiers) {
  const Q3Shader sh =
      parse_one("{ { map a.tga\n rgbGen const ( 0.5 0.25 1 )\n alphaGen const 0.75\n tcMod rotate 30\n tcGen environment } }");
  const Q3Stage& st = sh.stages.at(0);
  EXPECT_FLOAT_EQ(st.colour.x, 0.5f);
  EXPECT_FLOAT_EQ(st.colour.y, 0.25f);
  EXPECT_FLOAT_EQ(st.colour.z, 1.0f);
  EXPECT_FLOAT_EQ(st.colour.w, 0.75f);
  EXPECT_EQ(st.unsupported, (std::vector<std::string>{"tcMod rotate", "tcGen environment"}));
}

TEST(Q3Shader, LaterDefinitionsReplaceEarlierOnes) {
  Q3ShaderSet set;
  parse_q3_shader_script("a/b { { map one.tga } }", "1.shader", set);
  parse_q3_shader_script("A/B { { map two.tga } }", "2.shader", set);
  EXPECT_EQ(set.shaders.at("a/b").stages.at(0).image, "two.tga");
}

TEST(Q3Shader, MalformedScriptsLeaveNotesNotCrashes) {
  Q3ShaderSet set;
  parse_q3_shader_script("good { { map g.tga } }\nbroken {\n { map x.tga \n", "bad.shader", set);
  EXPECT_EQ(set.shaders.count("good"), 1u);
  ASSERT_FALSE(set.notes.empty());
  EXPECT_NE(set.notes[0].find("bad.shader:2"), std::string::npos) << set.notes[0];
  Q3ShaderSet other;
  parse_q3_shader_script("}}} name_without_body\n{{{{", "worse.shader", other);
  EXPECT_FALSE(other.notes.empty());
}

}  // namespace
}  // namespace oovr
