#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Check that every relative link and image path in Sightline's Markdown documentation resolves.

Usage: check_links.py SOURCE_ROOT

Reads README.md, Documentation/**/*.md, Modules/README.md, Benchmarks/README.md and
Data/README.md under SOURCE_ROOT and checks, outside fenced code blocks and inline code:

- Markdown links [text](target) and images ![alt](target), reference definitions
  "[label]: target", and HTML <img src="..."> and <a href="...">;
- targets with a scheme (http:, https:, mailto:, ...) are skipped;
- a relative target, with its #anchor and ?query removed and %-escapes decoded, must exist,
  resolved against the folder of the file that holds the link ("/..." against SOURCE_ROOT),
  and lie inside SOURCE_ROOT;
- an #anchor into a .md file (another one, or the same file for a pure "#anchor" link) must
  be the GitHub slug of one of its headings: the heading's text lowercased, punctuation other
  than hyphens and underscores removed, spaces turned into hyphens, "-1", "-2", ... appended to
  repeated slugs; <a name="..."> and id="..." anchors count too.

Prints one "file:line: target not found" line per broken link and exits with status 1, or
prints a one-line summary and exits with 0. Standard library only.
"""

import difflib
import os
import re
import sys
import urllib.parse

DOCUMENT_FILES = ["README.md", "Modules/README.md", "Benchmarks/README.md", "Data/README.md"]
DOCUMENT_FOLDERS = ["Documentation"]

FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
ATX_HEADING = re.compile(r"^ {0,3}(#{1,6})(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$")
SETEXT_UNDERLINE = re.compile(r"^ {0,3}(=+|-+)[ \t]*$")
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")
# [text](target "title"): the text may hold one level of brackets (an image inside a link)
# and span lines; the target is <...> or has balanced parentheses one level deep.
INLINE_LINK = re.compile(
    r"(!?)\[((?:[^\[\]]|\[[^\[\]]*\])*)\]"
    r"\(\s*(<[^<>\n]*>|(?:[^\s()]|\([^\s()]*\))*)"
    r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^()]*\)))?\s*\)")
REFERENCE_DEFINITION = re.compile(r"^ {0,3}\[([^\]]+)\]:[ \t]*(<[^<>\n]*>|\S+)", re.MULTILINE)
HTML_TARGET = re.compile(r"<(img|a)\b[^>]*?\b(src|href)\s*=\s*(\"[^\"]*\"|'[^']*')",
                         re.IGNORECASE)
HTML_ANCHOR = re.compile(r"<a\b[^>]*?\bname\s*=\s*(\"[^\"]*\"|'[^']*')|\bid\s*=\s*(\"[^\"]*\"|'[^']*')",
                         re.IGNORECASE)
HTML_TAG = re.compile(r"<[^>]*>")
BLANK_LINE = re.compile(r"[ \t]*(\n|$)")


def read_lines(path):
    with open(path, encoding="utf-8") as stream:
        return stream.read().split("\n")


def blank_fenced_code(lines):
    """The lines with fenced code blocks (fences included) replaced by empty lines."""
    out = []
    fence = None
    for line in lines:
        match = FENCE.match(line)
        if fence is None:
            if match:
                fence = match.group(1)
                out.append("")
                continue
            out.append(line)
        else:
            if match and match.group(1)[0] == fence[0] and len(match.group(1)) >= len(fence) \
                    and line.strip() == match.group(1):
                fence = None
            out.append("")
    return out


def blank_code_spans(text):
    """The text with the contents of inline code spans replaced by spaces (newlines kept).

    A span opens with a run of backticks and closes with a run of the same length; it may
    cross line ends but not a blank line. An unmatched run is literal text."""
    out = []
    i = 0
    n = len(text)
    while i < n:
        if text[i] != "`":
            out.append(text[i])
            i += 1
            continue
        j = i
        while j < n and text[j] == "`":
            j += 1
        run = j - i
        k = j
        close = -1
        while k < n:
            if text[k] == "`":
                m = k
                while m < n and text[m] == "`":
                    m += 1
                if m - k == run:
                    close = k
                    break
                k = m
                continue
            if text[k] == "\n" and BLANK_LINE.match(text, k + 1):
                break  # a blank line ends the paragraph
            k += 1
        if close < 0:
            out.append(text[i:j])
            i = j
            continue
        end = close + run
        out.append("".join(c if c == "\n" else " " for c in text[i:end]))
        i = end
    return "".join(out)


def heading_text(raw):
    text = re.sub(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]\([^)]*\)", r"\1", raw)  # links -> text
    text = HTML_TAG.sub("", text)
    return text.strip()


def github_slug(text):
    slug = text.strip().lower()
    slug = re.sub(r"[^\w\- ]", "", slug)
    return slug.replace(" ", "-")


_anchor_cache = {}


def anchors_of(path):
    """Every anchor GitHub gives the Markdown file at path."""
    if path in _anchor_cache:
        return _anchor_cache[path]
    lines = blank_fenced_code(read_lines(path))
    slugs = []
    seen = {}
    previous = ""
    for line in lines:
        text = None
        match = ATX_HEADING.match(line)
        if match:
            text = heading_text(match.group(2) or "")
        elif SETEXT_UNDERLINE.match(line) and previous.strip() and \
                not ATX_HEADING.match(previous) and not previous.lstrip().startswith(("|", "-", "*", ">")):
            text = heading_text(previous)
        if text is not None:
            slug = github_slug(text)
            if slug in seen:
                count = seen[slug]
                while "%s-%d" % (slug, count) in seen:
                    count += 1
                seen[slug] = count + 1
                slug = "%s-%d" % (slug, count)
            seen.setdefault(slug, 1)
            slugs.append(slug)
        for name_match in HTML_ANCHOR.finditer(line):
            value = (name_match.group(1) or name_match.group(2))[1:-1]
            slugs.append(value)
        previous = line
    _anchor_cache[path] = slugs
    return slugs


def links_in(path):
    """(line number, target) for every link, image and HTML src/href outside code."""
    lines = blank_fenced_code(read_lines(path))
    text = blank_code_spans("\n".join(lines))
    line_starts = [0]
    for index, char in enumerate(text):
        if char == "\n":
            line_starts.append(index + 1)

    def line_of(offset):
        low, high = 0, len(line_starts) - 1
        while low < high:
            middle = (low + high + 1) // 2
            if line_starts[middle] <= offset:
                low = middle
            else:
                high = middle - 1
        return low + 1

    found = []

    def scan(fragment, base):
        for match in INLINE_LINK.finditer(fragment):
            target = match.group(3)
            if target.startswith("<") and target.endswith(">"):
                target = target[1:-1]
            found.append((line_of(base + match.start(3)), target))
            scan(match.group(2), base + match.start(2))  # an image inside a link's text

    scan(text, 0)
    for match in REFERENCE_DEFINITION.finditer(text):
        target = match.group(2)
        if target.startswith("<") and target.endswith(">"):
            target = target[1:-1]
        found.append((line_of(match.start(2)), target))
    for match in HTML_TARGET.finditer(text):
        found.append((line_of(match.start(3)), match.group(3)[1:-1]))
    found.sort()
    return found


def check_file(root, path):
    problems = []
    relative = os.path.relpath(path, root)
    folder = os.path.dirname(path)
    for line, target in links_in(path):
        where = "%s:%d:" % (relative, line)
        stripped = target.strip()
        if not stripped:
            problems.append("%s empty link target" % where)
            continue
        if SCHEME.match(stripped) or stripped.startswith("//"):
            continue  # http(s), mailto and other external links
        file_part, _, anchor = stripped.partition("#")
        file_part = urllib.parse.unquote(file_part.partition("?")[0])
        anchor = urllib.parse.unquote(anchor)
        if file_part:
            if file_part.startswith("/"):
                resolved = os.path.normpath(os.path.join(root, file_part.lstrip("/")))
            else:
                resolved = os.path.normpath(os.path.join(folder, file_part))
            if os.path.commonpath([resolved, root]) != root:
                problems.append("%s %s not found (it points outside the source tree)" % (where, target))
                continue
            if not os.path.exists(resolved):
                problems.append("%s %s not found" % (where, target))
                continue
        else:
            resolved = path
        if anchor and resolved.endswith(".md") and os.path.isfile(resolved):
            anchors = anchors_of(resolved)
            if anchor not in anchors and anchor.lower() not in anchors:
                hint = difflib.get_close_matches(anchor.lower(), anchors, n=1)
                problems.append("%s %s not found (no heading with anchor #%s in %s%s)" % (
                    where, target, anchor, os.path.relpath(resolved, root),
                    "; did you mean #%s?" % hint[0] if hint else ""))
    return problems


def document_files(root):
    files = []
    missing = []
    for name in DOCUMENT_FILES:
        path = os.path.join(root, name)
        (files if os.path.isfile(path) else missing).append(path)
    for name in DOCUMENT_FOLDERS:
        folder = os.path.join(root, name)
        if not os.path.isdir(folder):
            missing.append(folder)
            continue
        for current, subfolders, names in os.walk(folder):
            subfolders.sort()
            files.extend(os.path.join(current, n) for n in sorted(names) if n.endswith(".md"))
    return files, missing


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: check_links.py SOURCE_ROOT\n")
        return 2
    root = os.path.realpath(argv[1])
    files, missing = document_files(root)
    problems = ["%s: file not found" % os.path.relpath(m, root) for m in missing]
    links = 0
    for path in files:
        links += len(links_in(path))
        problems.extend(check_file(root, path))
    if problems:
        print("Broken links in the documentation (%d):" % len(problems))
        for problem in problems:
            print(problem)
        return 1
    print("All %d links and image paths in %d Markdown files resolve." % (links, len(files)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
