// Quake 3 shader scripts: the chosen image, culling, nodraw/sky/fog, alpha
// test, tcMod scale, and tolerance of malformed scripts.
#include <gtest/gtest.h>

#include "oovr/scene/q3_shader.h"

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

TEST(Q3Shader, ReducesShadersToWhatIsDrawn) {
  Q3ShaderSet set;
  parse_q3_shader_script(kScript, "scripts/test.shader", set);
  EXPECT_TRUE(set.notes.empty()) << set.notes.front();
  ASSERT_EQ(set.shaders.size(), 7u);
  const Q3Shader& lit = set.shaders.at("textures/base/lit");
  EXPECT_EQ(lit.image, "textures/base/Lit.tga") << "the first stage with an image, not $lightmap";
  EXPECT_FALSE(lit.blended) << "a lightmap multiply (DST_COLOR ZERO) is how an opaque surface is lit";
  EXPECT_FLOAT_EQ(lit.tc_scale_s, 2);
  EXPECT_FLOAT_EQ(lit.tc_scale_t, 4);
  const Q3Shader& fence = set.shaders.at("textures/base/fence");
  EXPECT_TRUE(fence.two_sided);
  EXPECT_TRUE(fence.clamp);
  EXPECT_TRUE(fence.alpha_test);
  EXPECT_FLOAT_EQ(fence.alpha_cutoff, 0.5f);
  EXPECT_TRUE(set.shaders.at("textures/common/caulk").nodraw);
  EXPECT_TRUE(set.shaders.at("textures/skies/night").sky);
  EXPECT_EQ(set.shaders.at("textures/skies/night").image, "env/night_ft");
  EXPECT_TRUE(set.shaders.at("textures/fog/green").fog);
  EXPECT_EQ(set.shaders.at("textures/anim/fire").image, "textures/anim/fire1.tga");
  EXPECT_TRUE(set.shaders.at("textures/anim/fire").blended);
  EXPECT_EQ(set.shaders.at("textures/only/editor").image, "textures/only/editor.jpg");
}

TEST(Q3Shader, LaterDefinitionsReplaceEarlierOnes) {
  Q3ShaderSet set;
  parse_q3_shader_script("a/b { { map one.tga } }", "1.shader", set);
  parse_q3_shader_script("A/B { { map two.tga } }", "2.shader", set);
  EXPECT_EQ(set.shaders.at("a/b").image, "two.tga");
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
