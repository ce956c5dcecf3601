"""Each xacro 1.14 feature on a small document, with the XML Noetic's xacro makes of it, and the
errors it gives for bad input."""
import os
import textwrap

import pytest
import xacro

from xacro_xml_compare import canonical

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def expand(body, args=None, filename=None):
    doc = xacro.parse('<a %s>%s</a>' % (NS, body))
    xacro.process_doc(doc, mappings=dict(args or {}), filename=filename)
    return canonical(doc)


def same(body, result, **kw):
    assert expand(body, **kw) == canonical("<a>%s</a>" % result)


def fails(body, *fragments, **kw):
    with pytest.raises(xacro.XacroException) as e:
        expand(body, **kw)
    for fragment in fragments:
        assert fragment in str(e.value)
    return str(e.value)


# ---- the xacro. namespace and the other namespaces ----
def test_namespaced_functions(capsys):
    same('<b v="${xacro.tokenize(\'a,b; c\')}" w="${python.sorted([3, 1])}" x="${math.floor(2.5)}"'
         ' y="${xacro.dotify(dict(k=4)).k}" z="${xacro.arg(\'n\')}"/>',
         '<b v="[\'a\', \'b\', \'c\']" w="[1, 3]" x="2" y="4" z="7"/>', args={"n": "7"})
    assert capsys.readouterr().err == ""


def test_direct_use_of_moved_functions_warns(capsys):
    same('<b v="${sorted([2, 1])}"/>', '<b v="[1, 2]"/>')
    assert "Use python.sorted() instead" in capsys.readouterr().err


def test_messages_print_on_stderr_and_leave_no_text(capsys):
    same('<b>${xacro.message(\'hello\', 42)}</b><c>${xacro.warning(\'careful\')}</c>', "<b/><c/>")
    err = capsys.readouterr().err
    assert "hello 42" in err and "careful" in err
    assert "when processing file: string" in err   # warning() adds the location, message() not
    assert err.count("when processing file") == 1


def test_fatal_stops_with_its_message():
    fails("${xacro.fatal('no gripper for', 3)}", "no gripper for 3")


def test_print_location_names_macro_and_file(capsys):
    expand('<xacro:macro name="m" params="">${xacro.print_location()}</xacro:macro><xacro:m/>',
           filename="/robots/top.xacro")
    err = capsys.readouterr().err
    assert "when instantiating macro: m (/robots/top.xacro)" in err
    assert "in file: /robots/top.xacro" in err


def test_xacro_arg_of_an_unknown_argument_names_the_fix():
    fails("<b v=\"${xacro.arg('nope')}\"/>", "nope:=<value>", '<xacro:arg name="nope"')


def test_dirname_names_the_folder_of_the_file_being_read(tmp_path):
    same('<b d="$(dirname)"/>', '<b d="%s"/>' % tmp_path, filename=str(tmp_path / "robot.xacro"))


def test_arg_default_and_command_line():
    body = '<xacro:arg name="x" default="1"/><b v="$(arg x)" w="${xacro.arg(\'x\')}"/>'
    same(body, '<b v="1" w="1"/>')
    same(body, '<b v="5" w="5"/>', args={"x": "5"})


# ---- YAML ----
@pytest.fixture
def yaml_file(tmp_path):
    path = tmp_path / "params.yaml"
    path.write_text(textwrap.dedent("""\
        joint:
          limit: {lower: !degrees -90, upper: !radians pi/4, reach: !millimeters 850}
          inches: !inches 1
          feet: !foot 1
          meters: !meters 2
        links:
          - {name: a, mass: 1.5}
          - {name: b, mass: 2.5}
        """))
    return str(path)


def test_load_yaml_with_units_and_dotted_access(yaml_file):
    same('<xacro:property name="p" value="${xacro.load_yaml(\'%s\')}"/>'
         '<b lo="${p.joint.limit.lower}" up="${p[\'joint\'][\'limit\'].upper}" r="${p.joint.limit.reach}"'
         ' i="${p.joint.inches}" f="${p.joint.feet}" m="${p.joint.meters}"'
         ' n="${\' \'.join(l.name for l in p.links)}" w="${p.links[1].mass}"'
         ' h="${\'nope\' in p.joint}"/>' % yaml_file,
         '<b lo="%r" up="%r" r="0.85" i="0.0254" f="0.3048" m="2.0" n="a b" w="2.5" h="False"/>'
         % (-90 * 3.141592653589793 / 180, 3.141592653589793 / 4),
         args={})


def test_load_yaml_is_relative_to_the_including_file(yaml_file):
    top = os.path.join(os.path.dirname(yaml_file), "robot.xacro")
    same('<b v="${xacro.load_yaml(\'params.yaml\').links[0].name}"/>', '<b v="a"/>', filename=top)


def test_load_yaml_missing_key_is_an_attribute_error(yaml_file):
    fails('<b v="${xacro.load_yaml(\'%s\').joint.nope}"/>' % yaml_file, "no key 'nope'")


def test_load_yaml_bad_unit_expression(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("angle: !degrees ninety\n")
    fails('<b v="${xacro.load_yaml(\'%s\')}"/>' % path, "!degrees", "ninety")


def test_load_yaml_missing_file():
    fails('<b v="${xacro.load_yaml(\'/no/such/file.yaml\')}"/>', "/no/such/file.yaml")


# ---- properties ----
def test_lazy_eval_by_default_and_greedy_on_request():
    same('<xacro:property name="s" value="1"/>'
         '<xacro:property name="lazy" value="${s * 10}"/>'
         '<xacro:property name="greedy" value="${s * 10}" lazy_eval="false"/>'
         '<xacro:property name="s" value="2"/><b lazy="${lazy}" greedy="${greedy}"/>',
         '<b lazy="20" greedy="10"/>')


def test_greedy_redefinition_from_the_previous_value():
    same('<xacro:property name="p" value="ABC"/>'
         '<xacro:property name="p" value="${p.lower()}" lazy_eval="false"/><b v="${p}"/>',
         '<b v="abc"/>')


def test_circular_lazy_definition_is_named():
    fails('<xacro:property name="a" value="${b}"/><xacro:property name="b" value="${a}"/><b v="${a}"/>',
          "circular variable definition: a -> b -> a", 'lazy_eval="false"')


def test_property_remove_default_and_name_from_expression():
    same('<xacro:property name="p" value="1"/><xacro:property name="p" remove="true"/>'
         '<xacro:property name="p" default="2"/><xacro:property name="p" default="3"/>'
         '<xacro:property name="n" value="q"/><xacro:property name="${n}" value="4"/>'
         '<b p="${p}" q="${q}"/>', '<b p="2" q="4"/>')


def test_literals_quotes_and_underscores():
    # a quoted macro argument stays text; a lazy property is read again (and becomes a number)
    same('<xacro:property name="f" value="0.5"/><xacro:property name="q" value="\'0.5\'"/>'
         '<xacro:property name="u" value="1_000"/>'
         '<xacro:macro name="m" params="s:=\'0.5\'"><b f="${f * 2}" q="${q * 2}" s="${s + \'1\'}"'
         ' u="${u + \'x\'}"/></xacro:macro><xacro:m/>', '<b f="1.0" q="1.0" s="0.51" u="1_000x"/>')


def test_property_scopes_parent_and_global():
    same('<xacro:macro name="m" params=""><xacro:macro name="n" params="">'
         '<xacro:property name="g" value="global" scope="global"/>'
         '<xacro:property name="p" value="parent" scope="parent"/></xacro:macro>'
         '<xacro:n/><c p="${p}"/></xacro:macro><xacro:m/><b g="${g}"/>',
         '<c p="parent"/><b g="global"/>')


def test_bad_property_names():
    fails('<xacro:property name="__x" value="1"/>', "double underscore")
    fails('<xacro:property name="a-b" value="1"/>', "valid python identifiers")


def test_hidden_names_are_refused():
    fails('<b v="${().__class__}"/>', "invalid name", "__class__")


def test_undefined_name_names_the_expression():
    fails('<b v="${nope + 1}"/>', "name 'nope' is not defined", "when evaluating expression 'nope + 1'")


# ---- macros ----
def test_macro_named_like_a_tag_is_only_called_with_the_prefix():
    same('<xacro:macro name="link" params="name"><link name="wrapped_${name}"/></xacro:macro>'
         '<link name="plain"/><xacro:link name="a"/>',
         '<link name="plain"/><link name="wrapped_a"/>')


def test_an_unprefixed_macro_call_is_plain_xml_as_in_noetic_with_a_warning_once(capsys):
    same('<xacro:macro name="HDL-32E" params="name"><sensor name="${name}"/></xacro:macro>'
         '<HDL-32E name="a"/><HDL-32E name="b"/><xacro:HDL-32E name="c"/>',
         '<HDL-32E name="a"/><HDL-32E name="b"/><sensor name="c"/>')
    err = capsys.readouterr().err
    assert err.count("<HDL-32E> is kept as an XML element") == 1, err
    assert "Write <xacro:HDL-32E ...> to call it" in err


def test_a_macro_named_like_a_urdf_element_does_not_warn_on_that_element(capsys):
    same('<xacro:macro name="link" params="name"><link name="w_${name}"/></xacro:macro><link name="p"/>',
         '<link name="p"/>')
    assert capsys.readouterr().err == ""


def test_unprefixed_xacro_words_are_plain_xml():
    same('<property name="p" value="1"/><macro name="m"/>', '<property name="p" value="1"/><macro name="m"/>')


def test_macro_parameters_defaults_quotes_forwarding_and_blocks():
    same('<xacro:property name="outer" value="from caller"/>'
         '<xacro:macro name="m" params="a b:=2 c=\'x y\' d:=${1+2} e:=^ f:=^|dflt *one **many">'
         '<r a="${a}" b="${b}" c="${c}" d="${d}" e="${e}" f="${f}"><xacro:insert_block name="one"/>'
         '<xacro:insert_block name="many"/></r></xacro:macro>'
         '<xacro:property name="e" value="E"/>'
         '<xacro:m a="1"><first/><wrapper><x/><y/></wrapper></xacro:m>',
         '<r a="1" b="2" c="x y" d="3" e="E" f="dflt"><first/><x/><y/></r>')


def test_macro_body_sees_the_callers_properties():
    same('<xacro:macro name="m" params="prefix=${arm_id}_"><b n="${prefix}x"/></xacro:macro>'
         '<xacro:property name="arm_id" value="panda"/><xacro:m/>', '<b n="panda_x"/>')


def test_macro_errors():
    fails('<xacro:nope/>', "unknown macro name: xacro:nope")
    fails('<xacro:macro name="m" params="a"/><xacro:m b="1"/>', 'Invalid parameter "b"')
    fails('<xacro:macro name="m" params="a"/><xacro:m/>', "Undefined parameters [a]")
    fails('<xacro:macro name="m" params="*b"/><xacro:m/>', "Not enough blocks")
    fails('<xacro:macro name="m" params="a:=^"/><xacro:m/>', "Undefined property to forward: a")
    fails('<xacro:macro name="call" params=""/>', "Invalid use of macro name 'call'")
    fails('<xacro:macro name="a.b" params=""/>', "must not contain '.'")


def test_dynamic_macro_call():
    same('<xacro:macro name="m" params="v"><b v="${v}"/></xacro:macro>'
         '<xacro:property name="which" value="m"/><xacro:call macro="${which}" v="3"/>', '<b v="3"/>')


def test_conditionals_element_and_attribute():
    same('<xacro:if value="${1 == 1}"><yes/></xacro:if><xacro:unless value="true"><no/></xacro:unless>'
         '<xacro:element xacro:name="${\'dyn\'}"><xacro:attribute name="k" value="${2*2}"/></xacro:element>',
         '<yes/><dyn k="4"/>')
    fails('<xacro:if value="maybe"><x/></xacro:if>', 'Xacro conditional "maybe"', "not a boolean")


def test_escaped_dollar_braces():
    same('<b v="$${literal}" w="$$(arg x)"/>', '<b v="${literal}" w="$(arg x)"/>')
    fails('<b v="${unclosed"/>', "invalid expression", "$${")


# ---- includes ----
def test_include_with_namespace_optional_and_glob(tmp_path):
    (tmp_path / "part.xacro").write_text(
        '<r %s><xacro:property name="size" value="3"/>'
        '<xacro:macro name="m" params=""><p s="${size}"/></xacro:macro><xacro:m/></r>' % NS)
    top = str(tmp_path / "top.xacro")
    same('<xacro:include filename="part.xacro" ns="lib"/><xacro:lib.m/><b s="${lib.size}"/>'
         '<xacro:include filename="missing.xacro" optional="true"/>'
         '<xacro:include filename="p*.xacro"/>',
         '<p s="3"/><p s="3"/><b s="3"/><p s="3"/>', filename=top)


def test_missing_include_names_the_file_and_the_option(tmp_path):
    fails('<xacro:include filename="missing.xacro"/>', "missing.xacro", 'optional="true"',
          filename=str(tmp_path / "top.xacro"))


def test_comments_evaluated_only_when_asked():
    doc = xacro.parse('<a %s><!-- ${1+1} --><!-- xacro:eval-comments --><!-- ${2+2} --><b/>'
                      '<!-- ${3+3} --></a>' % NS)
    xacro.process_doc(doc)
    comments = [n.data for n in doc.documentElement.childNodes if n.nodeType == n.COMMENT_NODE]
    assert comments == [" ${1+1} ", " 4 ", " ${3+3} "]


def test_target_namespace_and_xacro_namespace_removed():
    doc = xacro.parse('<a %s xacro:targetNamespace="http://example.org/ns"><b/></a>' % NS)
    xacro.process_doc(doc)
    root = doc.documentElement
    assert root.getAttribute("xmlns") == "http://example.org/ns"
    assert not root.hasAttribute("xmlns:xacro") and not root.hasAttribute("xacro:targetNamespace")
