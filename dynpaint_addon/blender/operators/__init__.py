"""The add-on's operators, one module per job, and the menus that offer them.

common.py holds what they share (the poll mixin, run_and_report); each other module lists its
classes in CLASSES.
"""
import bpy

from . import (add, compositor, export, grease_pencil, image_slots, layers, paint_shape,
               painting, shape, turntable, web)

CLASSES = (*add.CLASSES, *layers.CLASSES, *grease_pencil.CLASSES, *turntable.CLASSES,
           *compositor.CLASSES, *painting.CLASSES, *image_slots.CLASSES, *export.CLASSES,
           *shape.CLASSES, *paint_shape.CLASSES, *web.CLASSES)


def menu_add(self, context):
    self.layout.menu(add.VIEW3D_MT_dynpaint_add.bl_idname, icon="IMAGE_RGB_ALPHA")


def menu_add_image(self, context):
    self.layout.operator(add.DYNPAINT_OT_add.bl_idname, text="Dynamic Painting",
                         icon="IMAGE_RGB_ALPHA")


def menu_import(self, context):
    self.layout.operator(add.DYNPAINT_OT_import_recipe.bl_idname,
                         text="Dynamic Painting Recipe (.toml)")


def menu_export(self, context):
    self.layout.operator(export.DYNPAINT_OT_export_recipe.bl_idname,
                         text="Dynamic Painting Recipe (.toml)")
    self.layout.operator(web.DYNPAINT_OT_export_web.bl_idname, text="Dynamic Painting (.html)")


def menu_compositor(self, context):
    space = context.space_data
    if getattr(space, "tree_type", "") == "CompositorNodeTree":
        self.layout.operator(compositor.DYNPAINT_OT_add_compositor_group.bl_idname,
                             icon="NODETREE")


MENUS = (("VIEW3D_MT_add", menu_add), ("VIEW3D_MT_image_add", menu_add_image),
         ("NODE_MT_add", menu_compositor), ("TOPBAR_MT_file_import", menu_import),
         ("TOPBAR_MT_file_export", menu_export))


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    for menu, fn in MENUS:
        getattr(bpy.types, menu).append(fn)


def unregister():
    for menu, fn in MENUS:
        getattr(bpy.types, menu).remove(fn)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
    add.forget_previews()
