"""The distance labels along the ground (the grid's `N m` tags, the rulers' labels)
never cover one another."""

import re

import pygame
import pytest

from puppet.app.camera import camera_for, subject_of
from puppet.app.render import draw_world
from puppet.data.catalog import load_setup
from puppet.session import Session

DISTANCE = re.compile(r"^-?[\d.]+ (m|cm)$")


class _Font:
    """A font that remembers which text each surface it renders shows."""

    def __init__(self, font, texts):
        self.font, self.texts = font, texts

    def render(self, text, *a):
        out = self.font.render(text, *a)
        self.texts[id(out)] = (text, out)
        return out

    def __getattr__(self, name):
        return getattr(self.font, name)


class _Surface(pygame.Surface):
    """A surface that notes where each image is blitted."""

    def __init__(self, size):
        super().__init__(size)
        self.blits_at = []
        self.kept = []  # every source, so that no id is reused for another

    def blit(self, source, dest, *a, **k):
        self.kept.append(source)
        self.blits_at.append((id(source), pygame.Rect(int(dest[0]), int(dest[1]),
                                                      *source.get_size())))
        return super().blit(source, dest, *a, **k)


def _labels(name, shift, scene=None):
    """The distance labels drawn with the camera on the character, moved ``shift`` m."""
    pygame.font.init()
    setup = load_setup(name, scene)
    session = Session(setup)
    camera = camera_for(setup)
    camera.resize(1280, 720)
    camera.follow(subject_of(session), None)
    camera.cx += shift
    surface, texts = _Surface((1280, 720)), {}
    draw_world(surface, session, camera, _Font(pygame.font.Font(None, 20), texts))
    return [(texts[i][0], rect) for i, rect in surface.blits_at
            if i in texts and DISTANCE.match(texts[i][0])]


@pytest.mark.parametrize("name, scene", [("biped-walk", None), ("biped-longjump", None),
                                         ("biped-longjump", "biped-longjump"),
                                         ("biped-auto", "biped-terrain")])
@pytest.mark.parametrize("shift", [0.0, 0.8, 3.3])
def test_distance_labels_do_not_overlap(name, scene, shift):
    """The rulers of biped-track and the long jump's scenes label the metres the grid
    labels too, or points a few cm beside them (-1 m and -90 cm)."""
    labels = _labels(name, shift, scene)
    assert len(labels) >= 3, labels
    for i, (a, ra) in enumerate(labels):
        for b, rb in labels[i + 1:]:
            assert not ra.colliderect(rb), (name, a, b)
