"""The generated blocks of docs/*.md: a study writes its tables between two HTML comment markers
(`<!-- name:begin -->`, `<!-- name:end -->`) and leaves the rest of the page as it is."""
import sys


def replace_block(doc, begin, end, block):
    """Put block between the markers begin and end of doc (exit 1 when they are missing)."""
    text = open(doc).read()
    if begin in text and end in text:
        text = text[:text.index(begin) + len(begin)] + block + text[text.index(end):]
        with open(doc, 'w') as f:
            f.write(text)
        print('wrote', doc, begin)
    else:
        print('markers', begin, end, 'not found in', doc, file=sys.stderr)
        sys.exit(1)
