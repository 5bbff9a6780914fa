"""YAML from outside, bounded before Drake's parser sees it: a document's size, its aliases'
expansion (a "billion laughs" of nested anchors is refused without being expanded), duplicate
keys (YAML lets the last one win silently; here every duplicate is refused, scene entries
included) and entry names that are not plain names (they become folder names). PyYAML composes
the document as a graph (an alias is a shared node, not a copy): the expanded size is counted
on it, memoised per node, in time linear in the document."""

import logging
import re

import yaml

from drake_car.law.checks import excerpt, read_input_file
from drake_car.law.road.profiles import MAX_ROAD_SAMPLES, ROAD_SAMPLE_BYTES, ROAD_SAMPLE_S
from drake_car.law.errors import InputError

# A scene file or --scene_text: the shipped scene files are a few kB; a !SampledProfile road
# of MAX_ROAD_SAMPLES points (law.road.profiles; a longer list is refused here, before Drake's
# parser spends ~0.15 ms a number on it) written out is about 2 x 20 bytes per point.
MAX_YAML_BYTES = 4_000_000
# Nodes of the document with every alias expanded (what a loader builds).
MAX_EXPANDED_NODES = 1_000_000
# A plain name: what a scene entry (and so a folder or file made from it) may be called.
PLAIN_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.+=-]{0,99}$")


class YamlInputError(InputError):
    """YAML refused before parsing; the message names where and why."""


def read_yaml_file(path, kind="scene file"):
    """The text of the YAML file ``path`` (a regular file under MAX_YAML_BYTES), checked by
    ``check_yaml``. A missing file, a folder, a device: YamlInputError naming it as what it
    should be (``kind``: a scene file, a car file)."""
    data = read_input_file(path, kind, limit=MAX_YAML_BYTES, is_text="YAML text",
                           error=YamlInputError)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise YamlInputError(f"{path}: not a text file (byte {e.start} is not UTF-8)") from None
    check_yaml(text, str(path))
    return text


def check_yaml(text, where):
    """Refuses ``text`` (YamlInputError naming ``where``) if it is over MAX_YAML_BYTES, would
    expand to over MAX_EXPANDED_NODES nodes, or has a duplicate key. Not YAML at all is left to
    the caller's parser (its message is the better one)."""
    size = len(text.encode("utf-8", "surrogatepass"))
    if size > MAX_YAML_BYTES:
        raise YamlInputError(f"{where}: {size} bytes of YAML; limited to {MAX_YAML_BYTES}")
    try:
        root = yaml.compose(text, Loader=yaml.CSafeLoader if hasattr(yaml, "CSafeLoader")
                            else yaml.SafeLoader)
    except yaml.YAMLError:
        return
    sizes = {}

    def expanded(node, key=None):
        known = sizes.get(id(node))
        if known is not None:
            return known
        sizes[id(node)] = MAX_EXPANDED_NODES + 1  # a node inside itself: refused
        if isinstance(node, yaml.MappingNode):
            keys = {}
            for key, _ in node.value:
                if isinstance(key, yaml.ScalarNode):
                    if key.value in keys and key.value != "<<":
                        raise YamlInputError(
                            f"{where}: line {key.start_mark.line + 1}: key "
                            f"{excerpt(key.value)} given twice (first on line "
                            f"{keys[key.value] + 1}); give each key once")
                    keys[key.value] = key.start_mark.line
            total = 1 + sum(expanded(k) + expanded(v, getattr(k, "value", None))
                            for k, v in node.value)
        elif isinstance(node, yaml.SequenceNode):
            if len(node.value) > MAX_ROAD_SAMPLES:
                n = len(node.value)
                raise YamlInputError(
                    f"{where}: line {node.start_mark.line + 1}: {excerpt(key)} is a list of {n} "
                    f"items; lists (a !SampledProfile's samples) are limited to "
                    f"{MAX_ROAD_SAMPLES} (about {n * ROAD_SAMPLE_S:.0f} s and "
                    f"{n * ROAD_SAMPLE_BYTES / 1e9:.1f} GB to load and settle [EST]); resample "
                    "the profile more coarsely")
            total = 1 + sum(expanded(v) for v in node.value)
        else:
            total = 1
        total = min(total, MAX_EXPANDED_NODES + 1)
        sizes[id(node)] = total
        if total > MAX_EXPANDED_NODES:
            raise YamlInputError(f"{where}: line {node.start_mark.line + 1}: its aliases "
                                 f"expand to over {MAX_EXPANDED_NODES} YAML nodes; refused "
                                 "(an alias bomb?)")
        return total

    if root is not None:
        expanded(root)


def check_entry_name(name, where):
    """Refuses a scene entry name that is not a plain name (it names folders and files)."""
    if not isinstance(name, str) or not PLAIN_NAME.match(name) or ".." in name:
        raise YamlInputError(f"{where}: scene entry name {excerpt(name)} is not a plain name "
                             "(letters, digits, _ . + = -; not starting with . or -; at most "
                             "100 characters); it names folders and files")


# A sampled road longer than this is announced with its cost (refused past MAX_ROAD_SAMPLES).
ANNOUNCE_ROAD_SAMPLES = 10_000


def announce_large_road(scene, where):
    """A sampled road past ANNOUNCE_ROAD_SAMPLES (law.road.profiles refuses past its limit)
    is announced with what it will cost before any work."""
    samples = len(getattr(scene.road, "x_m", ()))
    if samples > ANNOUNCE_ROAD_SAMPLES:
        logging.getLogger(__name__).warning("%s: road.x_m has %d samples: about %.0f s and %.2f GB to load and settle "
                    "[EST]", where, samples, samples * ROAD_SAMPLE_S,
                    samples * ROAD_SAMPLE_BYTES / 1e9)
