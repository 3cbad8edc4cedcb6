// tear: glTF accessors read with every range checked against the buffers first, for the glTF
// reader (read_gltf.cpp).
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "io/mesh/file_mesh.h"
#include "tear/error.h"

namespace tear::gltf {

/// Reads accessors with every range checked against the buffers first.
class AccessorReader {
 public:
  AccessorReader(const std::string& path, const tinygltf::Model& model, std::size_t file_size)
      : path_(path), model_(model), file_size_(file_size) {}

  /// `count * components` values of accessor `index` as `T`, normalized integers mapped to [0, 1]
  /// or [-1, 1] as glTF defines them (computed in double, then converted: a float component read as
  /// float is the float in the file). `what` names it in messages.
  template <class T>
  std::vector<T> read(int index, int components, const std::string& what) const {
    if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size()) {
      throw fail(what + " uses accessor " + std::to_string(index) + ", which does not exist");
    }
    const tinygltf::Accessor& accessor = model_.accessors[index];
    const std::string name = what + " (accessor " + std::to_string(index) + ")";
    const int type_components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
    if (type_components != components) {
      throw fail(name + " has " + std::to_string(type_components) + " components, expected " +
                 std::to_string(components));
    }
    const int component_size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType));
    if (component_size <= 0 || accessor.componentType == TINYGLTF_COMPONENT_TYPE_INT ||
        accessor.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE) {
      throw fail(name + " has the unknown component type " + std::to_string(accessor.componentType));
    }
    const std::uint64_t count = accessor.count;
    if (count > max_index_count) throw fail(name + " has too many elements (" + std::to_string(count) + ")");
    const std::uint64_t element_size = static_cast<std::uint64_t>(component_size) * components;

    std::vector<T> values;
    if (accessor.bufferView < 0) {
      // No data: zeros (to be replaced by sparse values). Bounded by the file's size so that a
      // tiny file cannot ask for gigabytes.
      if (count > file_size_) throw fail(name + " has " + std::to_string(count) + " elements and no data");
      values.assign(count * components, T(0));
    } else {
      std::uint64_t stride = 0;
      const unsigned char* data =
          view_data(accessor.bufferView, accessor.byteOffset, count, element_size, &stride, name);
      values.resize(count * components);
      if (std::is_same<T, float>::value && accessor.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
        // Floats as they are in the file: whole when tightly packed, else element by element.
        if (stride == element_size) {
          if (count > 0) std::memcpy(values.data(), data, count * element_size);
        } else {
          for (std::uint64_t i = 0; i < count; ++i)
            std::memcpy(&values[i * components], data + i * stride, element_size);
        }
      } else {
        for (std::uint64_t i = 0; i < count; ++i) {
          for (int k = 0; k < components; ++k) {
            values[i * components + k] = static_cast<T>(component(data + i * stride + k * component_size, accessor));
          }
        }
      }
    }

    if (accessor.sparse.isSparse) {
      const auto& sparse = accessor.sparse;
      if (sparse.count < 0 || static_cast<std::uint64_t>(sparse.count) > count) {
        throw fail(name + " has " + std::to_string(sparse.count) + " sparse values for " + std::to_string(count) +
                   " elements");
      }
      const std::uint64_t sparse_count = static_cast<std::uint64_t>(sparse.count);
      const int index_size =
          tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(sparse.indices.componentType));
      if (sparse.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
          sparse.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
          sparse.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        throw fail(name + " has sparse indices of component type " + std::to_string(sparse.indices.componentType));
      }
      if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
        throw fail(name + " has a negative sparse offset");
      std::uint64_t index_stride = 0, value_stride = 0;
      const unsigned char* indices =
          view_data(sparse.indices.bufferView, static_cast<std::size_t>(sparse.indices.byteOffset), sparse_count,
                    index_size, &index_stride, name + " sparse indices");
      const unsigned char* data =
          view_data(sparse.values.bufferView, static_cast<std::size_t>(sparse.values.byteOffset), sparse_count,
                    element_size, &value_stride, name + " sparse values");
      // Sparse data is tightly packed whatever the views' strides say.
      index_stride = index_size;
      value_stride = element_size;
      for (std::uint64_t s = 0; s < sparse_count; ++s) {
        std::uint32_t target = 0;
        if (index_size == 1) target = indices[s];
        if (index_size == 2) {
          std::uint16_t v;
          std::memcpy(&v, indices + 2 * s, 2);
          target = v;
        }
        if (index_size == 4) std::memcpy(&target, indices + 4 * s, 4);
        if (target >= count) {
          throw fail(name + " has the sparse index " + std::to_string(target) + " of " + std::to_string(count) +
                     " elements");
        }
        for (int k = 0; k < components; ++k) {
          values[static_cast<std::size_t>(target) * components + k] =
              static_cast<T>(component(data + s * value_stride + k * component_size, accessor));
        }
      }
      (void)index_stride;
    }
    return values;
  }

  Error fail(const std::string& what) const { return input_error(path_, what); }

 private:
  /// The bytes of `count` elements of `element_size` at `offset` in buffer view `view_index`, all
  /// of them inside the view and the view inside its buffer.
  const unsigned char* view_data(int view_index, std::size_t offset, std::uint64_t count, std::uint64_t element_size,
                                 std::uint64_t* stride, const std::string& name) const {
    if (view_index < 0 || static_cast<std::size_t>(view_index) >= model_.bufferViews.size()) {
      throw fail(name + " uses buffer view " + std::to_string(view_index) + ", which does not exist");
    }
    const tinygltf::BufferView& view = model_.bufferViews[view_index];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size()) {
      throw fail("buffer view " + std::to_string(view_index) + " uses buffer " + std::to_string(view.buffer) +
                 ", which does not exist");
    }
    const std::vector<unsigned char>& buffer = model_.buffers[view.buffer].data;
    const std::uint64_t view_offset = view.byteOffset, view_length = view.byteLength;
    if (view_offset > buffer.size() || view_length > buffer.size() - view_offset) {
      throw fail("buffer view " + std::to_string(view_index) + " (bytes " + std::to_string(view_offset) + " + " +
                 std::to_string(view_length) + ") reaches past the end of its buffer of " +
                 std::to_string(buffer.size()) + " bytes");
    }
    *stride = view.byteStride ? view.byteStride : element_size;
    if (*stride < element_size) {
      throw fail(name + ": buffer view " + std::to_string(view_index) + " has a stride of " + std::to_string(*stride) +
                 " bytes, less than an element's " + std::to_string(element_size));
    }
    if (count > 0) {
      // offset + stride * (count - 1) + element_size <= view_length, without overflow.
      const std::uint64_t last = count - 1;
      const bool fits = offset <= view_length && element_size <= view_length - offset &&
                        (last == 0 || *stride <= (view_length - offset - element_size) / last);
      if (!fits) {
        throw fail(name + ": " + std::to_string(count) + " elements at offset " + std::to_string(offset) +
                   " reach past the end of buffer view " + std::to_string(view_index) + " (" +
                   std::to_string(view_length) + " bytes)");
      }
    }
    return buffer.data() + view_offset + offset;
  }

  static double component(const unsigned char* at, const tinygltf::Accessor& accessor) {
    const bool normalized = accessor.normalized;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const double v = static_cast<std::int8_t>(*at);
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? *at / 255.0 : *at;
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, at, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, at, 2);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, at, 4);
        return normalized ? v / 4294967295.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        std::memcpy(&v, at, 4);
        return v;
      }
    }
    return 0.0;
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  std::size_t file_size_;
};

}  // namespace tear::gltf
