"""The one kind of error a user can fix (no bpy): a missing file, an unreadable image, a bad
recipe or option. Each part of the package raises its own subclass (RecipeError, ImageReadError,
ImageWriteError, ShapeError, ExportError, CommandError), and the command line ends any of them
with one line `error: …` (cli.main), never a traceback."""


class UserError(ValueError):
    """A problem the user can fix; the message says what and where, in one line."""


class CommandError(UserError):
    """A command-line option that cannot be used; the message names the option."""
