"""`penumbra render --denoise`'s second step: python3 -m penumbra.denoise_exr NOISY OUT.

Reads the EXR NOISY that `render` wrote, denoises its rgb (penumbra.denoise, with its
"albedo" and "normal" layers as OIDN's auxiliary images when the scene asked for them) and
writes OUT: the same layers and header, then "denoised" (channels denoised.R/G/B, named in
penumbra:aovs). write_exr writes OUT whole or not at all. `--check` only imports what the
denoiser needs, so that `render` can refuse before rendering. Errors: one line on stderr,
exit status 2 for bad input or a missing module, 1 otherwise (as the command line's).
"""

import sys


def check():
    """Imports pyoidn (penumbra.denoise imports it lazily); ImportError with the install hint."""
    from .denoise import _pyoidn

    _pyoidn()


def denoise_file(noisy, out):
    import penumbra

    layers = penumbra.read_exr(noisy)
    aux = {name: layers[name] for name in ("albedo", "normal") if name in layers}
    if "normal" in aux and "albedo" not in aux:
        del aux["normal"]  # OIDN uses a normal only with an albedo
    layers["denoised"] = penumbra.denoise(layers["rgb"], **aux)
    penumbra.write_exr(out, layers)


def main(argv):
    try:
        if argv == ["--check"]:
            check()
        elif len(argv) == 2:
            denoise_file(*argv)
        else:
            print("usage: python3 -m penumbra.denoise_exr (--check | NOISY.exr OUT.exr)", file=sys.stderr)
            return 2
    except (ImportError, ValueError) as error:  # a missing module; SceneError (a bad file)
        print(one_line(error), file=sys.stderr)
        return 2
    except Exception as error:  # RenderError (cannot write OUT), OIDN failing
        print(one_line(error), file=sys.stderr)
        return 1
    return 0


def one_line(error):
    text = str(error).strip()
    return text.splitlines()[0] if text else type(error).__name__


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
